// Scene values that imply more memory or time than a run may take are
// refused before anything runs: the master program, run as a user runs it,
// exits within 2 s and under 256 MiB naming the scene file and the key.
// Each of these took seconds to minutes, gigabytes, or ran on and reported
// another cause, before the limits were derived from the values.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <chrono>
#include <fstream>
#include <string>

#include "process_support.hpp"
#include "test_support.hpp"

namespace railcosim {
namespace {

// The base: the irregular-track car scene (it has an [irregularity] table).
std::string base_scene() {
  return test::read_file(test::source_path("scenes/car_irregular.toml"));
}

std::string mutate(std::string text, const std::string& section, const std::string& line) {
  // Replaces the whole [section] table by `line` (appended to an empty one).
  const auto start = text.find("[" + section + "]");
  if (start == std::string::npos) return text + "\n[" + section + "]\n" + line + "\n";
  auto end = text.find("\n[", start + 1);
  if (end == std::string::npos) end = text.size();
  return text.substr(0, start) + "[" + section + "]\n" + line + "\n" + text.substr(end);
}

std::string replace_key(std::string text, const std::string& key_prefix, const std::string& line) {
  const auto at = text.find("\n" + key_prefix);
  if (at == std::string::npos) return text;
  const auto end = text.find('\n', at + 1);
  return text.substr(0, at + 1) + line + text.substr(end);
}

struct Refusal {
  std::string scene, key, why;
};

std::vector<Refusal> mutants(const std::filesystem::path& dir) {
  const std::string base = base_scene();
  const std::string random = "model = \"random\"\nfra_class = 5\nwavelength_max = 30.0\nseed = 1\n";
  std::vector<Refusal> out;
  auto add = [&](const std::string& name, const std::string& text, const std::string& key,
                 const std::string& why) {
    const auto path = dir / (name + ".toml");
    std::ofstream(path) << text;
    out.push_back({path.string(), key, why});
  };
  add("grid_step",
      mutate(base, "irregularity", random + "wavelength_min = 1.524\ngrid_step = 1e-12"),
      "irregularity.grid_step", "grid points");
  add("grid_step_work",
      mutate(base, "irregularity", random + "wavelength_min = 1.524\ngrid_step = 1e-4"),
      "irregularity.grid_step", "components");
  add("wavelength_min", mutate(base, "irregularity", random + "wavelength_min = 1e-9"),
      "irregularity.wavelength_min", "grid points");
  add("dipped_joint",
      mutate(base, "irregularity",
             "model = \"dipped_joint\"\nposition = 10.0\nlength = 0.5\ndepth = 1e30"),
      "irregularity.depth", "0.17 m");
  add("dev_zero", mutate(base, "irregularity", "model = \"csv\"\nfile = \"/dev/zero\""),
      "irregularity.file", "not a regular file");
  add("passwd", mutate(base, "irregularity", "model = \"csv\"\nfile = \"/etc/passwd\""),
      "irregularity.file", "x_m,r_m");
  add("tolerance", replace_key(base, "tolerance", "tolerance = 1e-30"), "simulation.tolerance",
      "round-off");
  add("macro_steps", replace_key(base, "macro_step", "macro_step = 1e-8"), "simulation.end_time",
      "macro steps");
  add("micro_steps", replace_key(base, "tolerance", "tolerance = 1e-7\nmicro_steps = 65536"),
      "simulation.micro_steps", "fixed micro steps");
  return out;
}

TEST(SceneLimits, RefusedWithinTwoSecondsUnder256MiBNamingFileAndKey) {
  const auto dir = test::temp_dir("scene_limits");
  for (const Refusal& m : mutants(dir)) {
    SCOPED_TRACE(m.scene);
    const auto t0 = std::chrono::steady_clock::now();
    const test::Outcome o =
        test::run_master("run --scene " + m.scene +
                         " --case rs-xx-jacobi --transport inproc --out " + (dir / "out").string());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_NE(o.status, 0) << o.output;
    EXPECT_LT(seconds, 2.0) << o.output;
    EXPECT_NE(o.output.find(m.scene), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("'" + m.key + "'"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find(m.why), std::string::npos) << o.output;
  }
  // The largest resident set of any master run above (the children waited for).
  rusage r{};
  ASSERT_EQ(getrusage(RUSAGE_CHILDREN, &r), 0);
  EXPECT_LT(r.ru_maxrss, 256L * 1024) << "KiB";
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace railcosim
