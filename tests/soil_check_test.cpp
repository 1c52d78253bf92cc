// The soil's own check before a run (master/remote/soil_check.cpp) against
// a soil program that crashes, and one that crashes after forking a child
// that keeps its stderr open: the crash is reported at once by its signal
// (not as "no answer within" the deadline), and the child is killed with
// it. The soil program is a stand-in module under RAILCOSIM_FE_SOIL.
#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "cosim_case.hpp"
#include "remote/soil_check.hpp"
#include "scene.hpp"

namespace railcosim::remote {
namespace soil_check_test {

namespace fs = std::filesystem;

// A folder holding green_soil/participant.py with `body`, as RAILCOSIM_FE_SOIL.
class StandInSoil {
 public:
  explicit StandInSoil(const std::string& body) {
    std::string name = (fs::temp_directory_path() / "soil-check-XXXXXX").string();
    if (::mkdtemp(name.data()) == nullptr) throw std::runtime_error("mkdtemp");
    root_ = name;
    fs::create_directories(root_ / "green_soil");
    std::ofstream(root_ / "green_soil" / "__init__.py") << "";
    std::ofstream(root_ / "green_soil" / "participant.py") << body;
    ::setenv("RAILCOSIM_FE_SOIL", root_.c_str(), 1);
  }
  ~StandInSoil() {
    ::unsetenv("RAILCOSIM_FE_SOIL");
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  const fs::path& root() const { return root_; }

 private:
  fs::path root_;
};

// Runs the check with a 20 s deadline; returns its message and the seconds it took.
std::pair<std::string, double> check() {
  const Scene scene = load_scene(RAILCOSIM_SOURCE_DIR "/scenes/ground_vibration_green_ci.toml");
  const auto t0 = std::chrono::steady_clock::now();
  std::string message;
  try {
    check_started_soil(scene, parse_case("ss-xt-jacobi"), scene.macro_step,
                       std::chrono::seconds(20));
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  return {message, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
}

TEST(SoilCheck, ACrashIsReportedByItsSignal) {
  const StandInSoil soil(
      "import os, signal, sys\n"
      "sys.stderr.write('about to fail\\n'); sys.stderr.flush()\n"
      "os.kill(os.getpid(), signal.SIGSEGV)\n");
  const auto [message, seconds] = check();
  EXPECT_NE(message.find("it was ended by signal 11 (Segmentation fault): about to fail"),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find("no answer within"), std::string::npos) << message;
  EXPECT_LT(seconds, 10.0);
}

TEST(SoilCheck, AForkedChildDiesWithItAndDoesNotHoldTheCheck) {
  const StandInSoil soil("");
  const fs::path pid_file = soil.root() / "child.pid";
  std::ofstream(soil.root() / "green_soil" / "participant.py")
      << "import os, signal, time\n"
         "if os.fork() == 0:\n"
         "    open('"
      << pid_file.string()
      << "', 'w').write(str(os.getpid()))\n"
         "    time.sleep(120)\n"
         "    os._exit(0)\n"
         "while not os.path.exists('"
      << pid_file.string()
      << "'):\n"
         "    time.sleep(0.01)\n"
         "time.sleep(0.2)\n"
         "os.kill(os.getpid(), signal.SIGABRT)\n";
  const auto [message, seconds] = check();
  EXPECT_NE(message.find("it was ended by signal 6 (Aborted)"), std::string::npos) << message;
  EXPECT_LT(seconds, 10.0);
  std::ifstream in(pid_file);
  pid_t child = 0;
  ASSERT_TRUE(in >> child) << "the stand-in soil did not fork";
  // Killed: gone, or a zombie until whoever adopted it reaps it.
  bool gone = false;
  for (int k = 0; k < 100 && !gone; ++k) {
    std::ifstream stat("/proc/" + std::to_string(child) + "/stat");
    std::string text;
    std::getline(stat, text);
    const auto close = text.rfind(')');
    gone = !stat || (close != std::string::npos && text.compare(close + 2, 1, "Z") == 0);
    if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_TRUE(gone) << "the soil's child " << child << " outlived the check";
  if (!gone) ::kill(child, SIGKILL);
}

}  // namespace soil_check_test
}  // namespace railcosim::remote
