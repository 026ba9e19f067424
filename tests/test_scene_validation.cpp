// Every class of invalid input is rejected with one message that names the key, before any
// particle is made (parse_scene does all checks; nothing is written to disk).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/error.hpp"
#include "base/vec3.hpp"
#include "scene/fill.hpp"
#include "scene/scene.hpp"

using namespace tumble;

namespace {
std::string error_of(const std::string& toml, const std::vector<std::string>& o = {}) {
  try {
    parse_scene(toml, o, "test.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SceneValidation, DefaultsAreValid) { EXPECT_EQ(error_of(""), ""); }

TEST(SceneValidation, UnknownKeyIsNamedWithASuggestion) {
  const std::string m = error_of("[contact]\nrestituton = 0.9\n");
  EXPECT_NE(m.find("contact.restituton"), std::string::npos) << m;
  EXPECT_NE(m.find("did you mean 'contact.restitution'"), std::string::npos) << m;
  EXPECT_NE(error_of("", {"nosuch.key=1"}).find("nosuch.key"), std::string::npos);
}

// The scene text every output file carries (a checkpoint's, which a resume reads) holds each
// text value as given: a quote or a backslash in a path made it unreadable; a newline or a byte
// that is not UTF-8 cannot be written so, and is refused naming the key.
TEST(SceneValidation, TextValuesReadBackFromTheSceneText) {
  const std::string dir = "/tmp/q\"o\\x y";
  const Scene s = parse_scene("", {"scene.output_dir=" + dir, "scene.name=a\tb"}, "t");
  const Scene back = parse_scene(scene_to_text(s), {}, "its text");
  EXPECT_EQ(back.output_dir, dir);
  EXPECT_EQ(back.name, "a\tb");
  for (const std::string& bad : {std::string("two\nlines"), std::string("n\xff")}) {
    const std::string m = error_of("", {"scene.name=" + bad});
    EXPECT_NE(m.find("'scene.name' must be UTF-8 text without control characters"),
              std::string::npos)
        << m;
  }
}

TEST(SceneValidation, OutOfRangeValuesNameKeyAndRange) {
  const std::string m = error_of("[contact]\nrestitution = 1.5\n");
  EXPECT_NE(m.find("contact.restitution"), std::string::npos) << m;
  EXPECT_NE(m.find("[0.05, 1]"), std::string::npos) << m;
  EXPECT_NE(error_of("", {"contact.friction=-0.1"}).find("contact.friction"), std::string::npos);
  EXPECT_NE(error_of("", {"protocol.theta_z=400"}).find("protocol.theta_z"), std::string::npos);
  EXPECT_NE(error_of("", {"particles.density_ratio=11"}).find("particles.density_ratio"),
            std::string::npos);
}

TEST(SceneValidation, LargeFractionOutsideUnitInterval) {
  for (const char* f : {"-0.01", "1.01"}) {
    const std::string m = error_of("", {std::string("particles.large_fraction=") + f});
    EXPECT_NE(m.find("particles.large_fraction"), std::string::npos) << m;
    EXPECT_NE(m.find("[0, 1]"), std::string::npos) << m;
  }
}

TEST(SceneValidation, WrongTypesAndChoices) {
  EXPECT_NE(error_of("[contact]\nfriction = \"high\"\n").find("contact.friction"),
            std::string::npos);
  EXPECT_NE(error_of("", {"protocol.mode=wobble"}).find("biaxial, single_axis, rest"),
            std::string::npos);
  EXPECT_NE(error_of("", {"fill.seed=1.5"}).find("fill.seed"), std::string::npos);
  EXPECT_NE(error_of("[contact\n").find("not valid TOML"), std::string::npos);
}

TEST(SceneValidation, TimeStepAboveTheStabilityBound) {
  const Scene ok = parse_scene("", {}, "t");
  const double bound = time_step_bound(ok);
  // Yu law: the wall contact is the stiffest, ω0² = (π/t_c)² + γ_n², damping rate γ_n; the damped
  // chain bound (√(4γ² + ω0²) − 2γ)/ω0² is 0.291 t_c at e = 0.87 (t_c/π = 0.318 t_c undamped).
  const double g = -std::log(ok.restitution) / ok.collision_time;
  const double w0 = std::sqrt(std::pow(kPi / ok.collision_time, 2) + g * g);
  EXPECT_NEAR(bound, (std::sqrt(4 * g * g + w0 * w0) - 2 * g) / (w0 * w0), 1e-12 * bound);
  EXPECT_NEAR(bound / ok.collision_time, 0.291, 0.001);
  const std::string m = error_of("", {"time.dt=" + std::to_string(1.01 * bound)});
  EXPECT_NE(m.find("time.dt"), std::string::npos) << m;
  EXPECT_NE(m.find("stability bound"), std::string::npos) << m;
  EXPECT_EQ(error_of("", {"time.dt=" + std::to_string(0.99 * bound)}), "");
  EXPECT_NE(error_of("", {"time.dt_fraction=0.5"}).find("time.dt_fraction"), std::string::npos);
}

TEST(SceneValidation, BedThatDoesNotFit) {
  const std::string m =
      error_of("", {"particles.fill_level=0.9", "particles.packing_fraction=0.7"});
  EXPECT_NE(m.find("does not fit"), std::string::npos) << m;
  EXPECT_NE(m.find("particles.fill_level"), std::string::npos) << m;
  EXPECT_NE(error_of("", {"tumbler.radius=0.01"}).find("tumbler.radius"), std::string::npos);
}

TEST(SceneValidation, NothingIsWrittenForAnInvalidScene) {
  const auto dir = std::filesystem::temp_directory_path() / "tumble_invalid_scene";
  std::filesystem::remove_all(dir);
  error_of("", {"scene.output_dir=" + dir.string(), "fill.bed_cache=" + dir.string(),
                "contact.restitution=2"});
  EXPECT_FALSE(std::filesystem::exists(dir));
}

TEST(SceneValidation, ResolvedSceneRoundTrips) {
  const Scene a = parse_scene("", {"contact.restitution=0.5", "scene.name=x"}, "t");
  const Scene b = parse_scene(scene_to_text(a), {}, "t");
  EXPECT_EQ(a.resolved, b.resolved);
  EXPECT_EQ(b.restitution, 0.5);
}

// A scene file must say something: an empty, blank or comment-only file, a directory, or a file
// without [scene] name is refused with the file named (before: each ran the default scene).
TEST(SceneValidation, SceneFileMustNameItself) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(TUMBLE_TEST_SCRATCH) / "scene_files";
  fs::create_directories(dir);
  auto refusal = [&](const std::string& name, const std::string& text) {
    const fs::path p = dir / name;
    std::ofstream(p) << text;
    try {
      (void)load_scene(p.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refusal("empty.toml", "").find("is empty"), std::string::npos);
  EXPECT_NE(refusal("comments.toml", "# x\n").find("only comments"), std::string::npos);
  const std::string unnamed = refusal("unnamed.toml", "[tumbler]\nradius = 0.02\n");
  EXPECT_NE(unnamed.find("unnamed.toml' has no [scene] name"), std::string::npos) << unnamed;
  EXPECT_EQ(refusal("named.toml", "[scene]\nname = \"x\"\n[tumbler]\nradius = 0.02\n"), "");
  try {
    (void)load_scene(dir.string());
    ADD_FAILURE() << "a directory was read as a scene";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
}

// A scene far beyond memory or the uint32 indices is refused from arithmetic, at once, with the
// estimate (before: --check hung in the bed plan or ended in std::bad_alloc).
TEST(SceneValidation, HugeScenesAreRefusedWithTheEstimate) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string m = error_of("", {"particles.d_small=1e-5", "particles.d_large=1e-5"});
  EXPECT_NE(m.find("too large"), std::string::npos) << m;
  EXPECT_NE(m.find("particles"), std::string::npos) << m;
  set_memory_limit(100e6, "a 100 MB test limit");
  const std::string r = error_of("", {"tumbler.radius=0.2"});  // ~1.4e6 particles, ~1.3 GiB
  set_memory_limit(0, "");
  EXPECT_NE(r.find("more memory than a 100 MB test limit"), std::string::npos) << r;
  EXPECT_EQ(error_of("", {"tumbler.radius=0.2"}), "");  // no limit: only the indices bound it
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  // The estimate is the plan's own counts before rounding (each species to the nearest whole).
  const Scene s = parse_scene("", {}, "t");
  EXPECT_NEAR(estimate_resources(s).particles, static_cast<double>(planned_particle_count(s)), 1.0);
}

TEST(SceneValidation, ReposeIsMeasuredByDefaultOrANumberInRange) {
  const Scene d = parse_scene("");
  EXPECT_TRUE(d.repose_pending());
  EXPECT_NE(scene_to_text(d).find("protocol.repose = \"measured\""), std::string::npos);
  EXPECT_FALSE(parse_scene(scene_to_text(d)).repose.known);  // the word reads back
  const Scene n = parse_scene("", {"protocol.repose=30"});
  EXPECT_FALSE(n.repose_pending());
  EXPECT_EQ(n.repose.deg, 30.0);
  // Not biaxial: nothing to tilt, nothing to measure.
  EXPECT_FALSE(parse_scene("", {"protocol.mode=single_axis"}).repose_pending());
  const std::string word = error_of("[protocol]\nrepose = \"measure\"\n");
  EXPECT_NE(word.find("'protocol.repose' = 'measure' must be a number in [0, 89] or 'measured'"),
            std::string::npos)
      << word;
  const std::string range = error_of("", {"protocol.repose=90"});
  EXPECT_NE(range.find("out of range [0, 89] or 'measured'"), std::string::npos) << range;
  const std::string weightless = error_of("", {"gravity.g=0"});
  EXPECT_NE(weightless.find("'protocol.repose' = 'measured' needs gravity.g > 0"),
            std::string::npos)
      << weightless;
  EXPECT_EQ(error_of("", {"gravity.g=0", "protocol.repose=27"}), "");
  // A measured value fills the scene and its resolved text alike.
  Scene m = d;
  set_measured_repose(m, 26.5);
  EXPECT_EQ(parse_scene(scene_to_text(m)).repose.deg, 26.5);
  EXPECT_EQ(m.resolved.at("protocol.repose"), "26.5");
}

TEST(SceneValidation, StillSlopeIsANumberOrMeasuredForARigidBulk) {
  const Scene d = parse_scene("");
  EXPECT_TRUE(d.bulk_still_slope.known);
  EXPECT_EQ(d.bulk_still_slope.deg, 0.0);  // off
  const std::vector<std::string> rigid = {"fidelity.bulk=rigid", "protocol.repose=27",
                                          "fidelity.bulk_still_slope=measured"};
  const Scene m = parse_scene("", rigid);
  EXPECT_TRUE(m.still_slope_pending());
  EXPECT_TRUE(m.bed_turn_pending());  // the turn measures it, though β is given
  EXPECT_FALSE(m.repose_pending());
  EXPECT_FALSE(parse_scene(scene_to_text(m)).bulk_still_slope.known);  // the word reads back
  // A dynamic bulk never freezes: nothing to measure.
  EXPECT_FALSE(parse_scene("", {"protocol.repose=27", "fidelity.bulk_still_slope=measured"})
                   .bed_turn_pending());
  std::vector<std::string> weightless = rigid;
  weightless.push_back("gravity.g=0");
  const std::string e = error_of("", weightless);
  EXPECT_NE(e.find("'fidelity.bulk_still_slope' = 'measured' needs gravity.g > 0"),
            std::string::npos)
      << e;
  const std::string range = error_of("", {"fidelity.bulk_still_slope=95"});
  EXPECT_NE(range.find("out of range [0, 89] or 'measured'"), std::string::npos) << range;
  Scene filled = m;
  set_measured_still_slope(filled, 11.5);
  EXPECT_FALSE(filled.bed_turn_pending());
  EXPECT_EQ(parse_scene(scene_to_text(filled)).bulk_still_slope.deg, 11.5);
  EXPECT_EQ(filled.resolved.at("fidelity.bulk_still_slope"), "11.5");
}

// `--list-keys` names the margin that "measured" takes off the creep onset: the number the code
// uses, written as a stream writes it, so that a change of the constant shows in the help.
TEST(SceneValidation, StillSlopeHelpNamesTheMarginInUse) {
  std::ostringstream margin;
  margin << "less " << kStillSlopeMargin << " degrees";
  for (const KeySpec& k : scene_schema())
    if (k.key == "fidelity.bulk_still_slope") {
      EXPECT_NE(k.help.find(margin.str()), std::string::npos) << k.help;
      return;
    }
  ADD_FAILURE() << "fidelity.bulk_still_slope is not in the schema";
}
