// Every class of invalid input is rejected with one message that names the key, before any
// particle is made (parse_scene does all checks; nothing is written to disk).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "base/error.hpp"
#include "base/vec3.hpp"
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
