// `serve`, `batch` and `export` keep their plan store in the per-user state directory
// (${XDG_STATE_HOME:-~/.local/state}/slosh/plans.sqlite, directories created 0700), never in the
// directory they run from. The real binary runs with HOME / XDG_STATE_HOME in a temporary
// directory and its working directory elsewhere; the directory listings are the check.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "config/server_config.hpp"
#include "storage/state_dir.hpp"
#include "support/process.hpp"

namespace slosh::service {
namespace test_state_dir {

namespace fs = std::filesystem;
using test::TempDir;

/// Runs the binary with `args` in `cwd` with exactly `env` as its environment; stdout and
/// stderr go to files in `cwd`'s parent. Returns the child's pid.
pid_t spawn_in(const std::vector<std::string>& args, const fs::path& cwd,
               const std::map<std::string, std::string>& env, const fs::path& logs) {
  std::vector<std::string> storage{SLOSH_BINARY};
  storage.insert(storage.end(), args.begin(), args.end());
  std::vector<std::string> env_storage;
  for (const auto& [k, v] : env) env_storage.push_back(k + "=" + v);
  std::vector<char*> argv, envp;
  for (std::string& a : storage) argv.push_back(a.data());
  for (std::string& e : env_storage) envp.push_back(e.data());
  argv.push_back(nullptr);
  envp.push_back(nullptr);
  const std::string out = (logs / "stdout").string(), err = (logs / "stderr").string();
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int in = ::open("/dev/null", O_RDONLY);
    if (o < 0 || e < 0 || in < 0 || ::chdir(cwd.c_str()) != 0) ::_exit(126);
    ::dup2(in, STDIN_FILENO);
    ::dup2(o, STDOUT_FILENO);
    ::dup2(e, STDERR_FILENO);
    ::execve(argv[0], argv.data(), envp.data());
    ::_exit(127);
  }
  return pid;
}

int run_in(const std::vector<std::string>& args, const fs::path& cwd,
           const std::map<std::string, std::string>& env, const fs::path& logs) {
  test::Child child(spawn_in(args, cwd, env, logs));
  return child.wait_for(std::chrono::seconds(120)).value_or(-1);
}

std::set<std::string> listing(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename());
  return names;
}

unsigned mode_of(const fs::path& p) {
  struct stat st {};
  if (::stat(p.c_str(), &st) != 0) return 0;
  return st.st_mode & 07777u;
}

const char* kRecipes =
    "recipe_id,radius_mm,fill_height_mm,fluid,stroke_mm,motion_time_s,strategy\n"
    "a,48.5,82,water,800,1.0,notch\n";
const char* kPlanRequest =
    R"({"format": {"container": {"radius_mm": 48.5}, "fill_height_mm": 82, "fluid": "water",
        "stroke_mm": 800, "motion_time_s": 1.0}, "strategy": "notch"})";

TEST(StateDirectory, ResolvesTheXdgStateHomeOrHomeFallback) {
  EXPECT_EQ(std::string(kDefaultCachePath), ServerConfig{}.cache_path);
  EXPECT_EQ(resolve_cache_path(kDefaultCachePath, {{"XDG_STATE_HOME", "/x/state"}, {"HOME", "/h"}}),
            "/x/state/slosh/plans.sqlite");
  EXPECT_EQ(resolve_cache_path(kDefaultCachePath, {{"HOME", "/h"}}),
            "/h/.local/state/slosh/plans.sqlite");
  // A relative XDG_STATE_HOME is invalid by the specification and ignored; so is an empty one.
  EXPECT_EQ(resolve_cache_path(kDefaultCachePath, {{"XDG_STATE_HOME", "rel"}, {"HOME", "/h"}}),
            "/h/.local/state/slosh/plans.sqlite");
  EXPECT_EQ(resolve_cache_path(kDefaultCachePath, {{"XDG_STATE_HOME", ""}, {"HOME", "/h"}}),
            "/h/.local/state/slosh/plans.sqlite");
  EXPECT_EQ(resolve_cache_path("plans.sqlite", {}), "plans.sqlite");
  EXPECT_EQ(resolve_cache_path("", {}), "");
  try {
    (void)resolve_cache_path(kDefaultCachePath, {});
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "cache = ${XDG_STATE_HOME}/slosh/plans.sqlite: neither XDG_STATE_HOME (an absolute "
              "path) nor HOME is set; give --cache FILE, or --cache \"\" for a memory-only cache");
  }
}

TEST(StateDirectory, BatchWritesItsStoreUnderHomeNotTheWorkingDirectory) {
  const TempDir tmp;
  fs::create_directories(tmp / "home");
  fs::create_directories(tmp / "work");
  test::write_file(tmp / "work" / "recipes.csv", kRecipes);
  const int code =
      run_in({"batch", "--in", "recipes.csv", "--out", "plans.csv", "--progress", "never"},
             tmp / "work", {{"HOME", (tmp / "home").string()}}, tmp / "home");
  ASSERT_EQ(code, 0) << test::read_file(tmp / "home" / "stderr");
  EXPECT_EQ(listing(tmp / "work"), (std::set<std::string>{"recipes.csv", "plans.csv"}));
  const fs::path state = tmp / "home" / ".local" / "state";
  EXPECT_TRUE(fs::exists(state / "slosh" / "plans.sqlite"));
  EXPECT_EQ(mode_of(tmp / "home" / ".local"), 0700u);
  EXPECT_EQ(mode_of(state), 0700u);
  EXPECT_EQ(mode_of(state / "slosh"), 0700u);
  // The second run is answered from that store.
  ASSERT_EQ(run_in({"batch", "--in", "recipes.csv", "--out", "again.csv", "--progress", "never"},
                   tmp / "work", {{"HOME", (tmp / "home").string()}}, tmp / "home"),
            0);
  EXPECT_NE(test::read_file(tmp / "work" / "again.csv").find(",true,"), std::string::npos)
      << test::read_file(tmp / "work" / "again.csv");
}

TEST(StateDirectory, ServeAndExportUseXdgStateHome) {
  const TempDir tmp;
  for (const char* d : {"home", "xdg", "work"}) fs::create_directories(tmp / d);
  const std::map<std::string, std::string> env{{"HOME", (tmp / "home").string()},
                                               {"XDG_STATE_HOME", (tmp / "xdg").string()}};
  test::write_file(tmp / "work" / "plan.json", kPlanRequest);
  ASSERT_EQ(run_in({"export", "--request", "plan.json", "--out", "cam.csv"}, tmp / "work", env,
                   tmp / "home"),
            0)
      << test::read_file(tmp / "home" / "stderr");
  EXPECT_TRUE(fs::exists(tmp / "xdg" / "slosh" / "plans.sqlite"));
  EXPECT_EQ(mode_of(tmp / "xdg" / "slosh"), 0700u);
  {
    test::Child server(
        spawn_in({"serve", "--port", "0", "--port-file", "port"}, tmp / "work", env, tmp / "home"));
    ASSERT_GT(test::wait_for_port(tmp / "work" / "port", server, std::chrono::seconds(30)), 0)
        << test::read_file(tmp / "home" / "stderr");
    ::kill(server.pid(), SIGTERM);
    EXPECT_EQ(server.wait_for(std::chrono::seconds(30)), 0);
  }
  EXPECT_EQ(listing(tmp / "work"), (std::set<std::string>{"plan.json", "cam.csv", "port"}));
  EXPECT_EQ(listing(tmp / "home"), (std::set<std::string>{"stdout", "stderr"}));
}

TEST(StateDirectory, WithoutHomeTheDefaultStopsTheStartNamingTheWayOut) {
  const TempDir tmp;
  fs::create_directories(tmp / "work");
  const int code = run_in({"serve", "--port", "0"}, tmp / "work", {}, tmp / "work");
  EXPECT_EQ(code, 2);
  EXPECT_EQ(test::read_file(tmp / "work" / "stderr"),
            "slosh serve: cache = ${XDG_STATE_HOME}/slosh/plans.sqlite: neither XDG_STATE_HOME "
            "(an absolute path) nor HOME is set; give --cache FILE, or --cache \"\" for a "
            "memory-only cache\n");
  EXPECT_EQ(listing(tmp / "work"), (std::set<std::string>{"stdout", "stderr"}));
}

}  // namespace test_state_dir
}  // namespace slosh::service
