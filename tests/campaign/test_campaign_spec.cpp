// Campaign files: validation messages name the key; expansion into cases is deterministic, with
// stable ids and seeds; slices partition the cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>

#include "base/error.hpp"
#include "campaign/campaign_spec.hpp"
#include "campaign/collect_plan.hpp"
#include "campaign/expand.hpp"

namespace tumble::campaign {
namespace {

const std::string kScene = std::string(TUMBLE_SOURCE_DIR) + "/scenes/bst_tiny.toml";

std::string with_campaign(const std::string& body, const std::string& campaign_extra = "") {
  return "[campaign]\nname = \"t\"\nscene = \"" + kScene + "\"\n" + campaign_extra + "\n" + body;
}

// The InputError message of parsing `text` ("" if it parses).
std::string error_of(const std::string& text) {
  try {
    (void)parse_campaign(text, "test.toml", ".");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CampaignSpec, RanksPerCaseIsAPositiveIntegerNamingTheKey) {
  for (const char* bad : {"ranks_per_case = 0", "ranks_per_case = -2", "ranks_per_case = 1.5",
                          "ranks_per_case = \"two\""}) {
    const std::string e = error_of(with_campaign("", bad));
    EXPECT_NE(e.find("key 'campaign.ranks_per_case'"), std::string::npos) << bad << ": " << e;
  }
  const std::string s = error_of(with_campaign("[[sweep]]\ntheta_z = 57\nranks_per_case = 0\n"));
  EXPECT_NE(s.find("key 'sweep[0].ranks_per_case'"), std::string::npos) << s;
  EXPECT_EQ(error_of(with_campaign("", "ranks_per_case = 4")), "");
}

// A sweep's ranks_per_case gives its points their own group size; the others keep the campaign's.
TEST(Expand, RanksPerCaseByCampaignAndBySweep) {
  const CampaignSpec s = parse_campaign(with_campaign(R"(
[[sweep]]
theta_z = [57, 90]
[[sweep]]
theta_z = 45
ranks_per_case = 4
)",
                                                      "ranks_per_case = 2"),
                                        "test.toml", ".");
  const Expansion e = expand(s);
  ASSERT_EQ(e.cases.size(), 3u);
  for (const Case& c : e.cases) {
    const bool big = c.params_text.find("theta_z=45") != std::string::npos;
    EXPECT_EQ(c.ranks, big ? 4 : 2) << c.params_text;
    EXPECT_EQ(c.ranks_key, big ? "sweep[1].ranks_per_case" : "campaign.ranks_per_case");
  }
}

// A parameter's scene key ("protocol.theta_z") is that parameter: two sweeps that name one point
// by either give one point (before: two points of the same seed and physics, run twice).
TEST(Expand, AParameterAndItsSceneKeyGiveOnePoint) {
  const CampaignSpec s = parse_campaign(with_campaign(R"(
[[sweep]]
theta_z = 57
"particles.large_fraction" = 0.2
[[sweep]]
"protocol.theta_z" = 57
f = 0.2
)"),
                                        "test.toml", ".");
  const Expansion e = expand(s);
  ASSERT_EQ(e.points.size(), 1u);
  EXPECT_NE(e.cases.front().params_text.find("theta_z=57;theta_x=57;f=0.2;"), std::string::npos)
      << e.cases.front().params_text;
}

TEST(CampaignSpec, UnknownKeysGetASuggestion) {
  const std::string e = error_of(with_campaign("", "replicaz = 3"));
  EXPECT_NE(e.find("unknown key 'campaign.replicaz'"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'campaign.replicas'"), std::string::npos) << e;
  const std::string s = error_of(with_campaign("[[sweep]]\ntheta_y = [1, 2]\n"));
  EXPECT_NE(s.find("unknown key 'sweep[0].theta_y'"), std::string::npos) << s;
  EXPECT_NE(s.find("did you mean 'theta_z'"), std::string::npos) << s;
}

TEST(CampaignSpec, ValuesAreCheckedAgainstTheirRanges) {
  EXPECT_NE(error_of(with_campaign("", "tier = \"ultra\""))
                .find("key 'campaign.tier' = 'ultra' is "
                      "not one of: standard, reference, fast, preview"),
            std::string::npos);
  EXPECT_NE(error_of(with_campaign("", "replicas = 0"))
                .find("key 'campaign.replicas' = 0 is out of "
                      "range"),
            std::string::npos);
  EXPECT_NE(error_of(with_campaign("", "replicas = 1.5")).find("must be an integer"),
            std::string::npos);
  EXPECT_NE(error_of(with_campaign("[[sweep]]\nsize_ratio = 0.5\n")).find("must be >= 1"),
            std::string::npos);
  EXPECT_NE(error_of(with_campaign("[collect]\niterations = [3, 2]\n")).find("'to' must be larger"),
            std::string::npos);
  EXPECT_NE(error_of("[campaign]\nname = \"x\"\n").find("key 'campaign.scene' is required"),
            std::string::npos);
  EXPECT_NE(error_of(with_campaign("[overrides]\n\"fill.seed\" = 3\n")).find("set by the campaign"),
            std::string::npos);
}

TEST(CampaignSpec, DisplacementLagMustBeWholeSamples) {
  const std::string e = error_of(
      with_campaign("[collect]\nsamples_per_iteration = 2\ndisplacement_periods = 0.75\n"));
  EXPECT_NE(e.find("key 'collect.displacement_periods' = 0.75 must be a whole multiple of 1 / "
                   "collect.samples_per_iteration"),
            std::string::npos)
      << e;
}

TEST(CampaignSpec, SeveralDisplacementLagsAreListedAndChecked) {
  const CampaignSpec s = parse_campaign(
      with_campaign("[collect]\ndisplacement_periods = [1, 6, 18]\n"), "test.toml", ".");
  EXPECT_EQ(s.collect.displacement_periods, (std::vector<double>{1, 6, 18}));
  EXPECT_EQ(s.collect.displacement_group(0), "displacement");
  EXPECT_EQ(s.collect.displacement_group(2), "displacement_k18");
  // One lag keeps the canonical text (and so the case ids) of before; a list is another plan.
  const CampaignSpec one =
      parse_campaign(with_campaign("[collect]\ndisplacement_periods = 1\n"), "test.toml", ".");
  EXPECT_NE(one.collect.canonical().find(";k=1;"), std::string::npos) << one.collect.canonical();
  EXPECT_NE(s.collect.canonical().find(";k=1,6,18;"), std::string::npos);
  EXPECT_NE(error_of(with_campaign("[collect]\ndisplacement_periods = [6, 6]\n")).find("twice"),
            std::string::npos);
  EXPECT_NE(error_of(with_campaign("[collect]\ndisplacement_periods = []\n"))
                .find("key 'collect.displacement_periods' must be a number or a list of 1 to 8"),
            std::string::npos);
  const std::string e = error_of(
      with_campaign("[collect]\nsamples_per_iteration = 2\ndisplacement_periods = [1, 0.75]\n"));
  EXPECT_NE(e.find("key 'collect.displacement_periods' = 0.75 must be a whole multiple"),
            std::string::npos)
      << e;
  // A lag longer than the window is refused when the cases are expanded, naming it.
  const CampaignSpec longer =
      parse_campaign(with_campaign("[overrides]\n\"protocol.iterations\" = 8\n[collect]\n"
                                   "iterations = [2, 8]\ndisplacement_periods = [1, 6, 18]\n"),
                     "test.toml", ".");
  try {
    (void)expand(longer);
    FAIL() << "expected an InputError";
  } catch (const InputError& x) {
    EXPECT_NE(std::string(x.what()).find("key 'collect.displacement_periods' = 18 periods do not "
                                         "fit in the window collect.iterations = [2, 8]"),
              std::string::npos)
        << x.what();
  }
}

TEST(CampaignSpec, CollectionWindowBeyondTheRunIsACampaignError) {
  const CampaignSpec s = parse_campaign(
      with_campaign("[overrides]\n\"protocol.iterations\" = 2\n[collect]\niterations = [1, 3]\n"),
      "test.toml", ".");
  try {
    (void)expand(s);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'collect.iterations' ends at iteration 3, after the "
                                         "run (protocol.iterations = 2)"),
              std::string::npos)
        << e.what();
  }
}

// Yu 2022 Sec. IV D: 2 vol % light, 98 vol % heavy, equal sizes. The shell "one diameter" is
// resolved per case from its own (tiered) scene, the roles name the light species as the mapped
// minority, and any other text is refused with the key.
TEST(CampaignSpec, DensityMixtureRolesAndTheOneDiameterShell) {
  const CampaignSpec s = parse_campaign(with_campaign(R"(
[[sweep]]
zip = true
size_ratio = 1
f = 0.98
R_rho = [3, 8]
"particles.density" = [2000, 1000]
[[sweep]]
size_ratio = 2
[collect]
shell_inner = "one_diameter"
)"),
                                        "test.toml", ".");
  EXPECT_TRUE(s.collect.shell_one_diameter);
  EXPECT_NE(s.collect.canonical().find("shell=one_diameter"), std::string::npos);
  const Expansion e = expand(s);
  int density = 0, size = 0;
  for (const auto& c : e.cases) {
    const Scene sc = case_scene(s, c, "/tmp/x", "/tmp/beds", 1);
    const CollectPlan plan = make_collect_plan(s.collect, sc);
    const Mixture& m = plan.mixture;
    if (m.kind == MixtureKind::density) {
      ++density;
      EXPECT_EQ(m.name[0], "light");
      EXPECT_EQ(m.name[1], "heavy");
      EXPECT_EQ(m.mapped, 0);
      EXPECT_EQ(m.minority, 0);
      EXPECT_NEAR(m.fraction[0], 0.02, 1e-15);
      EXPECT_TRUE((sc.density == 2000 && sc.density_ratio == 3) ||
                  (sc.density == 1000 && sc.density_ratio == 8));
      EXPECT_DOUBLE_EQ(plan.shell_inner, 1 - sc.d_small / sc.radius);
    } else {
      ++size;
      EXPECT_EQ(m.kind, MixtureKind::size);
      EXPECT_EQ(m.name[m.mapped], "large");
      EXPECT_DOUBLE_EQ(plan.shell_inner, 1 - sc.d_large / sc.radius);
    }
  }
  EXPECT_GT(density, 0);
  EXPECT_GT(size, 0);
  EXPECT_NE(error_of(with_campaign("[collect]\nshell_inner = \"two_diameters\"\n"))
                .find("collect.shell_inner"),
            std::string::npos);
}

TEST(Expand, ProductZipReplicasAndDensityBidisperse) {
  const CampaignSpec s = parse_campaign(with_campaign(R"(
[[sweep]]
theta_z = [57, 90]
theta_x = [57, 90]
f = 0.2
[[sweep]]
zip = true
theta_z = [60, 65]
theta_x = [75, 76]
replicas = 1
[[sweep]]
size_ratio = 1
R_rho = [3, 8]
)",
                                                      "replicas = 3\nseed = 7"),
                                        "test.toml", ".");
  const Expansion e = expand(s);
  EXPECT_EQ(e.points.size(), 4u + 2u + 2u);
  EXPECT_EQ(e.cases.size(), 4u * 3 + 2u * 1 + 2u * 3);
  // Zip pairs the lists element by element.
  std::set<std::string> zipped;
  for (const auto& p : e.points)
    if (p.params_text.find("theta_z=60") != std::string::npos ||
        p.params_text.find("theta_z=65") != std::string::npos)
      zipped.insert(p.params_text.substr(0, p.params_text.find(";f=")));
  EXPECT_EQ(zipped, (std::set<std::string>{"theta_z=60;theta_x=75", "theta_z=65;theta_x=76"}));
  // Density-bidisperse: equal diameters, heavier "large" species.
  int density_cases = 0;
  for (const auto& c : e.cases) {
    if (c.params_text.find("size_ratio=1") == std::string::npos) continue;
    ++density_cases;
    const Scene sc = case_scene(s, c, "/tmp/x", "/tmp/beds", 1);
    EXPECT_EQ(sc.d_large, sc.d_small);
    EXPECT_TRUE(sc.density_ratio == 3 || sc.density_ratio == 8);
  }
  EXPECT_EQ(density_cases, 6);
  // Ids are unique and reproducible; seeds are shared by cases that differ only in the protocol.
  std::set<std::string> ids;
  for (const auto& c : e.cases) ids.insert(c.id);
  EXPECT_EQ(ids.size(), e.cases.size());
  const Expansion again = expand(s);
  for (std::size_t k = 0; k < e.cases.size(); ++k) EXPECT_EQ(e.cases[k].id, again.cases[k].id);
  const Case& a = e.cases[0];  // theta (57, 57), replica 0
  const auto same_bed = std::find_if(e.cases.begin(), e.cases.end(), [&](const Case& c) {
    return c.replica == a.replica && c.point_id != a.point_id && c.bed_text == a.bed_text;
  });
  ASSERT_NE(same_bed, e.cases.end());
  EXPECT_EQ(case_seed(s, a, 1), case_seed(s, *same_bed, 1));
  EXPECT_NE(case_seed(s, e.cases[0], 1), case_seed(s, e.cases[1], 1));  // replicas differ
  EXPECT_EQ(case_seed(s, a, 1), case_seed(s, a, 2));  // retry_seed = "same" (the default)
}

TEST(Expand, NewSeedRetriesAndCampaignSeedChangeIds) {
  CampaignSpec s = parse_campaign(with_campaign("", "retry_seed = \"new\""), "test.toml", ".");
  const Expansion e = expand(s);
  ASSERT_EQ(e.cases.size(), 1u);
  EXPECT_NE(case_seed(s, e.cases[0], 1), case_seed(s, e.cases[0], 2));
  s.seed = 99;
  EXPECT_NE(expand(s).cases[0].id, e.cases[0].id);
}

TEST(Expand, AnInvalidCaseSceneIsRecordedNotThrown) {
  const CampaignSpec s =
      parse_campaign(with_campaign("[[sweep]]\n\"time.dt\" = [2e-5, 4e-4]\n"), "test.toml", ".");
  const Expansion e = expand(s);
  ASSERT_EQ(e.cases.size(), 2u);
  EXPECT_TRUE(e.cases[0].scene_error.empty());
  EXPECT_NE(e.cases[1].scene_error.find("key 'time.dt' gives a time step 0.0004 s above the "
                                        "stability bound"),
            std::string::npos)
      << e.cases[1].scene_error;
}

TEST(Slices, PartitionTheCasesDeterministicallyAndBalanceCost) {
  const CampaignSpec s = parse_campaign(with_campaign(R"(
[[sweep]]
theta_z = [30, 45, 57, 68, 90]
"protocol.iterations" = [1, 2, 3]
)",
                                                      "replicas = 2"),
                                        "test.toml", ".");
  const Expansion e = expand(s);
  ASSERT_EQ(e.cases.size(), 30u);
  for (int n : {1, 3, 7}) {
    std::vector<int> owner(e.cases.size(), 0);
    double lo = 1e300, hi = 0;
    for (int i = 1; i <= n; ++i) {
      const auto part = slice_cases(e, i, n);
      EXPECT_EQ(part, slice_cases(e, i, n));
      double cost = 0;
      for (auto k : part) {
        ++owner[k];
        cost += e.cases[k].cost;
      }
      lo = std::min(lo, cost);
      hi = std::max(hi, cost);
    }
    for (int o : owner) EXPECT_EQ(o, 1);  // every case in exactly one slice
    if (n == 3) {
      EXPECT_LT(hi / lo, 1.25);  // the snake deal balances the work
    }
  }
}

// A campaign's tier reaches every case's scene (derived from the template), the sweep's own keys
// still win, and the tier is part of the case id.
TEST(CampaignSpec, TierAppliesToEveryCase) {
  const std::string body = "[[sweep]]\nf = [0.1, 0.2]\n";
  const CampaignSpec fast = parse_campaign(with_campaign(body, "tier = \"fast\""), "t.toml", ".");
  const CampaignSpec standard = parse_campaign(with_campaign(body), "t.toml", ".");
  const Expansion ef = expand(fast), es = expand(standard);
  ASSERT_EQ(ef.cases.size(), es.cases.size());
  for (std::size_t k = 0; k < ef.cases.size(); ++k) {
    const Scene a = case_scene(fast, ef.cases[k], "/tmp/x", "/tmp/beds", 1);
    const Scene b = case_scene(standard, es.cases[k], "/tmp/x", "/tmp/beds", 1);
    EXPECT_DOUBLE_EQ(a.collision_time, 2 * b.collision_time);
    EXPECT_EQ(a.tier_applied, Tier::fast);
    EXPECT_DOUBLE_EQ(a.large_fraction, b.large_fraction);  // the sweep's value kept
    EXPECT_NE(ef.cases[k].id, es.cases[k].id);
  }
}

TEST(Expand, RigidBulkKeysEnterTheIdOnlyWhenTheBulkIsRigid) {
  // With a dynamic bulk its thresholds change nothing, and the ids stay those of campaigns made
  // before the keys existed; a rigid bulk, and then each threshold, gives other ids.
  CampaignSpec s = parse_campaign(with_campaign(""), "test.toml", ".");
  const std::string plain = expand(s).cases[0].id;
  s.overrides.push_back("fidelity.bulk_dwell=7");
  EXPECT_EQ(expand(s).cases[0].id, plain);
  s.overrides.push_back("fidelity.bulk=rigid");
  const std::string rigid = expand(s).cases[0].id;
  EXPECT_NE(rigid, plain);
  // The gravity rule (added later) at its default, off, leaves the rigid ids alone; on, it
  // enters them.
  s.overrides.push_back("fidelity.bulk_thaw_gravity=2");
  EXPECT_EQ(expand(s).cases[0].id, rigid);
  s.overrides.push_back("fidelity.bulk_thaw_gravity=0.5");
  EXPECT_NE(expand(s).cases[0].id, rigid);
  s.overrides.push_back("fidelity.bulk_thaw_gravity=2");
  // Likewise the segment-change thaw: on (as before the key) leaves the ids alone, off and omega
  // enter, each its own.
  s.overrides.push_back("fidelity.bulk_segment_thaw=on");
  EXPECT_EQ(expand(s).cases[0].id, rigid);
  s.overrides.push_back("fidelity.bulk_segment_thaw=off");
  const std::string off = expand(s).cases[0].id;
  EXPECT_NE(off, rigid);
  s.overrides.push_back("fidelity.bulk_segment_thaw=omega");
  EXPECT_NE(expand(s).cases[0].id, rigid);
  EXPECT_NE(expand(s).cases[0].id, off);
  s.overrides.push_back("fidelity.bulk_segment_thaw=on");
  // And the still surface: 0 (the surface layer never freezes, as before the key) leaves them.
  s.overrides.push_back("fidelity.bulk_still_slope=0");
  EXPECT_EQ(expand(s).cases[0].id, rigid);
  s.overrides.push_back("fidelity.bulk_still_slope=20");
  EXPECT_NE(expand(s).cases[0].id, rigid);
  s.overrides.push_back("fidelity.bulk_still_slope=0");
  s.overrides.push_back("fidelity.bulk_dwell=8");
  EXPECT_NE(expand(s).cases[0].id, rigid);
}

TEST(Expand, NewtonAcrossBordersStaysOutOfTheId) {
  // parallel.newton changes a run at round-off only (which rank sums a border pair), as the rank
  // count does: either value keeps the ids campaigns had before the key existed.
  CampaignSpec s = parse_campaign(with_campaign(""), "test.toml", ".");
  const std::string plain = expand(s).cases[0].id;
  for (const char* setting : {"parallel.newton=off", "parallel.newton=on"}) {
    s.overrides.push_back(setting);
    EXPECT_EQ(expand(s).cases[0].id, plain) << setting;
  }
  s.overrides.push_back("parallel.rebalance_threshold=1.5");  // (a key that does enter it)
  EXPECT_NE(expand(s).cases[0].id, plain);
}

TEST(Expand, ASweptRigidBulkHasItsThresholdsInItsId) {
  // A dynamic template swept to rigid: the template's hash leaves the bulk's keys out (they change
  // nothing while it is dynamic), so the rigid point's id must take them from its own scene, or a
  // change of a threshold would mix two settings in one point. The dynamic point keeps its id.
  CampaignSpec s = parse_campaign(
      with_campaign("[[sweep]]\n\"fidelity.bulk\" = [\"dynamic\", \"rigid\"]\n"), "test.toml", ".");
  const Expansion a = expand(s);
  s.overrides.push_back("fidelity.bulk_dwell=0.1");
  const Expansion b = expand(s);
  ASSERT_EQ(a.cases.size(), 2u);
  ASSERT_EQ(b.cases.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const bool rigid = a.cases[k].params_text.find("rigid") != std::string::npos;
    EXPECT_EQ(a.cases[k].id == b.cases[k].id, !rigid) << a.cases[k].params_text;
    EXPECT_EQ(a.cases[k].point_id == b.cases[k].point_id, !rigid) << a.cases[k].params_text;
  }
  // The gravity rule at its "off" value stays out here too, and so do the segment thaw on and
  // the still slope 0.
  s.overrides.back() = "fidelity.bulk_thaw_gravity=2";
  const Expansion c = expand(s);
  for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(a.cases[k].id, c.cases[k].id);
  s.overrides.back() = "fidelity.bulk_segment_thaw=on";
  const Expansion d = expand(s);
  for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(a.cases[k].id, d.cases[k].id);
  s.overrides.back() = "fidelity.bulk_still_slope=0";
  const Expansion e = expand(s);
  for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(a.cases[k].id, e.cases[k].id);
}

TEST(Expand, ASweptBulkOptionKeepsTheBedsCommon) {
  // dynamic against rigid is a paired comparison: the same replica runs on the same bed in both
  // points. A key that shapes the bed (the fill fraction) still gives another seed.
  const CampaignSpec s = parse_campaign(
      with_campaign("[[sweep]]\n\"fidelity.bulk\" = [\"dynamic\", \"rigid\"]\n", "replicas = 2"),
      "test.toml", ".");
  const Expansion e = expand(s);
  ASSERT_EQ(e.cases.size(), 4u);
  ASSERT_EQ(e.points.size(), 2u);
  for (const auto& a : e.cases)
    for (const auto& b : e.cases)
      if (a.point_id != b.point_id) {
        EXPECT_EQ(case_seed(s, a, 1) == case_seed(s, b, 1), a.replica == b.replica)
            << a.params_text << " / " << b.params_text;
      }
  const CampaignSpec f =
      parse_campaign(with_campaign("[[sweep]]\nf = [0.15, 0.3]\n"), "test.toml", ".");
  const Expansion ef = expand(f);
  ASSERT_EQ(ef.cases.size(), 2u);
  EXPECT_NE(case_seed(f, ef.cases[0], 1), case_seed(f, ef.cases[1], 1));
}

TEST(Expand, CasesRunLargestFirstThenReplicaByReplica) {
  // Two points of one cost (dynamic and rigid bulk: the cost model counts particles x steps) and
  // a longer protocol: the long point's cases start first; then replica 0 of both short points,
  // then replica 1, ..., so a campaign stopped part-way holds pairs, not one point's replicas.
  const std::string sweeps =
      "[[sweep]]\n\"fidelity.bulk\" = [\"dynamic\", \"rigid\"]\n[[sweep]]\ntheta_z = 120\n";
  const Expansion e =
      expand(parse_campaign(with_campaign(sweeps, "replicas = 3"), "test.toml", "."));
  ASSERT_EQ(e.cases.size(), 9u);
  std::vector<std::size_t> order(e.cases.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return runs_before(e.cases[a], e.cases[b]); });
  std::vector<std::string> got;
  for (std::size_t k : order) {
    const Case& c = e.cases[k];
    const std::string kind = c.params_text.find("theta_z=120") != std::string::npos ? "long"
                             : c.params_text.find("rigid") != std::string::npos     ? "rigid"
                                                                                    : "dynamic";
    got.push_back(kind + std::to_string(c.replica));
  }
  const std::vector<std::string> want = {"long0",    "long1",  "long2",    "dynamic0", "rigid0",
                                         "dynamic1", "rigid1", "dynamic2", "rigid2"};
  EXPECT_EQ(got, want);
  EXPECT_GT(e.cases[order[0]].cost, e.cases[order[3]].cost);
}

}  // namespace
}  // namespace tumble::campaign
