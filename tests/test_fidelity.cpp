// Fidelity tiers (scene/fidelity.hpp): each tier derives its values from the scene as written,
// --set keys win over them, and a tier that does not apply is refused with the key named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "base/error.hpp"
#include "io/bed_io.hpp"
#include "scene/fill.hpp"
#include "scene/scene.hpp"

using namespace tumble;

namespace {
// bst_paper's values (R = 70 mm, 4/2 mm, t_c = 5e-4 s, 3 rpm, 20 iterations).
const char* kPaper =
    "[tumbler]\nradius = 0.07\n[particles]\nd_small = 0.002\nd_large = 0.004\n"
    "[contact]\ncollision_time = 5e-4\n[protocol]\nmode = \"biaxial\"\nrpm = 3\niterations = 20\n";

Scene tier(const std::string& t, std::vector<std::string> o = {}) {
  o.push_back("fidelity.tier=" + t);
  return parse_scene(kPaper, o, "paper");
}
}  // namespace

TEST(Fidelity, StandardIsTheSceneAsWritten) {
  const Scene a = parse_scene(kPaper, {}, "paper"), b = tier("standard");
  EXPECT_EQ(scene_to_text(a), scene_to_text(b));
}

TEST(Fidelity, ReferenceIsStifferWithAFinerStep) {
  const Scene s = tier("reference");
  EXPECT_DOUBLE_EQ(s.collision_time, 2.5e-4);
  EXPECT_DOUBLE_EQ(s.time_step(), 2.5e-6);  // t_c / 100
  EXPECT_DOUBLE_EQ(s.d_large, 0.004);
  EXPECT_DOUBLE_EQ(s.rpm, 3);
  EXPECT_DOUBLE_EQ(s.iterations, 20);
}

TEST(Fidelity, FastAndPreviewCoarsenSpeedUpAndShorten) {
  const Scene f = tier("fast"), p = tier("preview");
  EXPECT_NEAR(f.radius / f.d_large, 8.75, 1e-9);
  EXPECT_NEAR(p.radius / p.d_large, 5, 1e-9);
  EXPECT_NEAR(f.d_large / f.d_small, 2, 1e-12);  // size ratio kept
  EXPECT_NEAR(p.d_large / p.d_small, 2, 1e-12);
  // Froude number omega^2 R / g raised to the tier's floor.
  EXPECT_NEAR(f.omega() * f.omega() * f.radius / f.g, 3e-3, 1e-9);
  EXPECT_NEAR(p.omega() * p.omega() * p.radius / p.g, 1e-2, 1e-9);
  EXPECT_DOUBLE_EQ(f.collision_time, 1e-3);
  EXPECT_DOUBLE_EQ(p.collision_time, 2e-3);
  EXPECT_NEAR(f.time_step(), 1e-3 / 30, 1e-15);
  EXPECT_NEAR(p.time_step(), 2e-3 / 20, 1e-15);
  EXPECT_DOUBLE_EQ(f.iterations, 10);
  EXPECT_DOUBLE_EQ(p.iterations, 3);
  EXPECT_DOUBLE_EQ(f.skin, 0.2);
  EXPECT_DOUBLE_EQ(p.skin, 0.3);
  // Settling allowed as many collision times as the scene allows.
  EXPECT_DOUBLE_EQ(f.settle_max_time, 2 * tier("standard").settle_max_time);
  EXPECT_DOUBLE_EQ(p.settle_max_time, 4 * tier("standard").settle_max_time);
  EXPECT_DOUBLE_EQ(tier("reference").settle_max_time, tier("standard").settle_max_time);
  // Each tier is cheaper than the one above it (particles x steps).
  auto cost = [](const Scene& s) {
    return static_cast<double>(planned_particle_count(s)) * s.run_time() / s.time_step();
  };
  EXPECT_GT(cost(tier("reference")), cost(tier("standard")));
  EXPECT_GT(cost(tier("standard")), cost(f));
  EXPECT_GT(cost(f), cost(p));
}

TEST(Fidelity, SetKeysWinOverTheTier) {
  const Scene s = tier("preview", {"protocol.iterations=7", "contact.collision_time=1e-3"});
  EXPECT_DOUBLE_EQ(s.iterations, 7);
  EXPECT_DOUBLE_EQ(s.collision_time, 1e-3);
  EXPECT_NEAR(s.radius / s.d_large, 5, 1e-9);  // the rest of the tier still applies
}

// A given diameter does not escape the tier's coarsening: both diameters grow by one factor, so
// an equal-size (density-bidisperse) pair stays equal and reaches the tier's R/d bound.
TEST(Fidelity, CoarseningKeepsAGivenSizeRatio) {
  const Scene s = tier("fast", {"particles.d_large=0.002"});
  EXPECT_DOUBLE_EQ(s.d_large, s.d_small);
  EXPECT_NEAR(s.radius / s.d_large, 8.75, 1e-9);
  const Scene t = tier("fast", {"particles.d_large=0.006"});
  EXPECT_NEAR(t.d_large / t.d_small, 3, 1e-11);  // the tier writes 12 significant digits
  EXPECT_NEAR(t.radius / t.d_large, 8.75, 1e-9);
}

TEST(Fidelity, TiersAreRefusedForCylindersAndUnknownNames) {
  try {
    parse_scene(
        "[tumbler]\nshape = \"cylinder\"\nradius = 10\nlength = 40\n[contact]\nlaw = "
        "\"rapaport2007\"\n[time]\ndt = 0.005\n",
        {"fidelity.tier=fast"}, "cyl");
    ADD_FAILURE() << "a cylinder with a tier was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fidelity.tier"), std::string::npos) << e.what();
  }
  try {
    tier("ultra");
    ADD_FAILURE() << "an unknown tier was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("standard, reference, fast, preview"), std::string::npos)
        << e.what();
  }
}

// The resolved text of a tiered scene reads back to the same values (checkpoints and provenance
// re-parse it): the tier is recorded as applied, not applied twice.
TEST(Fidelity, ResolvedTextReadsBackUnchanged) {
  const Scene s = tier("reference");
  EXPECT_EQ(s.tier_applied, Tier::reference);
  const Scene again = parse_scene(scene_to_text(s), {}, "resolved");
  EXPECT_DOUBLE_EQ(again.collision_time, s.collision_time);
  EXPECT_EQ(again.tier_applied, Tier::reference);
  EXPECT_EQ(scene_to_text(again), scene_to_text(s));
}

// A bed settled with the soft contacts of a cheap tier presses further into the wall than a stiff
// one; reading it back must accept what the scene's contacts allow (up to the validator's
// kMaxWeightOverlap of d_small) and still refuse a bed that belongs to a smaller tumbler.
TEST(Fidelity, SoftTierBedsReadBack) {
  const Scene s = parse_scene(kPaper, {}, "paper");
  const std::string dir = ::testing::TempDir();
  auto bed_pressing_in = [&](double depth) {
    Particles p;
    p.resize(1);
    p.radius[0] = 0.5 * s.d_small;
    p.x[0] = {0, -(s.radius - p.radius[0] + depth), 0};
    p.id[0] = 0;
    io::write_bed(dir + "/bed.h5", p, s, 1);
  };
  bed_pressing_in(0.2 * s.d_small);  // beyond 10% of a radius, within the allowed overlap
  EXPECT_NO_THROW(io::read_bed(dir + "/bed.h5", s));
  bed_pressing_in(0.3 * s.d_small);
  EXPECT_THROW(io::read_bed(dir + "/bed.h5", s), InputError);
}

// Beds are validated before any work (issue 21, docs/guarantees.md "Bed validation"): each bad
// bed is refused as bad input naming the row; the same damage in a cached bed is corrupt input.
TEST(BedValidation, BadBedsAreRefusedWithTheRowNamed) {
  const Scene s = parse_scene(kPaper, {}, "paper");
  const std::string path = ::testing::TempDir() + "/bed_validation.h5";
  // Four small particles in a row on the floor, one diameter apart: a valid bed.
  auto good = [&] {
    Particles p;
    p.resize(4);
    for (std::size_t i = 0; i < 4; ++i) {
      p.id[i] = static_cast<std::int64_t>(i);
      p.radius[i] = 0.5 * s.d_small;
      p.x[i] = {(static_cast<double>(i) - 1.5) * s.d_small, -0.5 * s.radius, 0};
    }
    return p;
  };
  auto message = [&](const Particles& p, io::BedSource source = io::BedSource::User) {
    io::write_bed(path, p, s, 1);
    try {
      io::read_bed(path, s, source);
    } catch (const CorruptInputError& e) {
      return std::string("corrupt: ") + e.what();
    } catch (const InputError& e) {
      return std::string("input: ") + e.what();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(good()), "accepted");
  Particles p = good();
  p.id[2] = 1;
  EXPECT_NE(message(p).find("input: bed '" + path + "', row 2: id 1 appears twice"),
            std::string::npos);
  p = good();
  p.id[3] = 1000000000000;
  EXPECT_NE(message(p).find("row 3: id 1000000000000 is outside [0, 4)"), std::string::npos);
  p = good();
  p.species[1] = 7;
  EXPECT_NE(message(p).find("row 1: species 7"), std::string::npos);
  p = good();
  p.x[0].y = std::nan("");
  EXPECT_NE(message(p).find("row 0: the position is not finite"), std::string::npos);
  p = good();
  p.x[3] = p.x[2];
  EXPECT_NE(message(p).find("the particles of row 2 and row 3 overlap"), std::string::npos);
  p = good();
  p.x[3].x = 2 * s.radius;
  EXPECT_NE(message(p).find("row 3: particle 3 lies outside the tumbler"), std::string::npos);
  EXPECT_NE(message(Particles{}).find("holds no particles"), std::string::npos);
  // Tumble's own cache: the same damage is a corrupt file (exit 3), not bad input.
  p = good();
  p.species[1] = 7;
  EXPECT_EQ(message(p, io::BedSource::Cache).rfind("corrupt: ", 0), 0u);
}

// A text bed (the LIGGGHTS format) names the line: an unknown type, a duplicate id.
TEST(BedValidation, TextBedsNameTheLine) {
  const Scene s = parse_scene(kPaper, {}, "paper");
  const std::string path = ::testing::TempDir() + "/bed_validation.txt";
  auto message = [&](const std::string& text) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    std::fputs(text.c_str(), f);
    std::fclose(f);
    try {
      io::read_bed(path, s);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // Gravity along -z in the file: z = -R/2 is Tumble's y = -R/2.
  char a[128], b[128];
  std::snprintf(a, sizeof a, "1 1 %.17g 0 0 %.17g\n", s.d_small, -0.5 * s.radius);
  std::snprintf(b, sizeof b, "2 1 %.17g %.17g 0 %.17g\n", s.d_small, s.d_small, -0.5 * s.radius);
  EXPECT_EQ(message(std::string("# id type d x y z\n") + a + b), "accepted");
  std::string bad = b;
  bad[2] = '9';  // type 9
  EXPECT_NE(message(std::string("# id type d x y z\n") + a + bad).find("line 3: particle type 9"),
            std::string::npos);
  bad = b;
  bad[0] = '1';  // id 1 twice
  EXPECT_NE(
      message(std::string("# id type d x y z\n") + a + bad).find("line 3: id 1 appears twice"),
      std::string::npos);
  EXPECT_NE(message("# nothing\n").find("holds no particles"), std::string::npos);
}
