// Randomised corruption of the example scenes (drivers/scenes/*.yaml and
// tests/data/scenes/*.yaml): Scene::parse must either succeed or throw
// cms::InputError. Any other exception, a crash or a hang fails the test.
// Each seed file runs in a child process so that a crash is reported with
// the case that caused it. CMS_FUZZ_ITERATIONS sets the cases per seed.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "cms/core/Error.hpp"
#include "cms/scene/Scene.hpp"

namespace fs = std::filesystem;

namespace {

int iterations() {
  const char* env = std::getenv("CMS_FUZZ_ITERATIONS");
  return env && *env ? std::atoi(env) : 400;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream is(text);
  for (std::string l; std::getline(is, l);) out.push_back(l);
  return out;
}

/// One reproducible mutation of `text`: case `k` of `seed`.
std::string mutate(const std::string& text, unsigned seed, int k) {
  std::mt19937 rng(seed * 1000003u + static_cast<unsigned>(k));
  auto ls = lines(text);
  const char* nasty[] = {":", "[", "]", "{", "}", "- ", "-1e309", "nan", "1e308", "\t", "'", "\"", "&a", "*a",
                         "!!binary", "? ", "|", ">", "#", "0x7fffffffffffffff", "Kind: C", "Parent: bus",
                         "Elements: 1000001", "Rate: -1", "Area: 0", "[1, 2]", "~", "null", "{a: b}"};
  const int ops = 1 + static_cast<int>(rng() % 3);
  for (int o = 0; o < ops && !ls.empty(); ++o) {
    const std::size_t i = rng() % ls.size();
    switch (rng() % 7) {
      case 0: ls.erase(ls.begin() + i); break;
      case 1: ls.insert(ls.begin() + i, ls[rng() % ls.size()]); break;
      case 2: std::swap(ls[i], ls[rng() % ls.size()]); break;
      case 3: if (!ls[i].empty()) ls[i][rng() % ls[i].size()] = static_cast<char>(rng() % 128); break;
      case 4: ls[i].insert(rng() % (ls[i].size() + 1), nasty[rng() % (sizeof nasty / sizeof *nasty)]); break;
      case 5: ls[i] = ls[i].substr(0, rng() % (ls[i].size() + 1)); break;
      default: ls.resize(i + 1); break;
    }
  }
  std::string out;
  for (const auto& l : ls) out += l + "\n";
  return out;
}

}  // namespace

TEST(SceneFuzz, CorruptedScenesSucceedOrAreInputErrors) {
  std::vector<fs::path> seeds;
  for (const auto& dir : {fs::path(CMS_SCENE_DIR), fs::path(CMS_TEST_DATA_DIR) / "scenes"})
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".yaml") seeds.push_back(e.path());
  std::sort(seeds.begin(), seeds.end());
  ASSERT_GE(seeds.size(), 5u);
  const int n = iterations();
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    std::ifstream in(seeds[s]);
    std::stringstream text;
    text << in.rdbuf();
    int pipeFd[2];
    ASSERT_EQ(pipe(pipeFd), 0);
    const pid_t pid = fork();
    if (pid == 0) {
      close(pipeFd[0]);
      alarm(120);
      for (int k = 0; k < n; ++k) {
        const std::string m = mutate(text.str(), static_cast<unsigned>(s), k);
        try {
          cms::scene::Scene::parse(m, seeds[s].string());
        } catch (const cms::InputError&) {
        } catch (const std::exception& e) {
          const std::string msg = "case " + std::to_string(k) + ": " + typeid(e).name() + ": " + e.what();
          if (write(pipeFd[1], msg.data(), msg.size()) < 0) {}
          _exit(3);
        }
      }
      _exit(0);
    }
    close(pipeFd[1]);
    char buf[2048];
    const ssize_t got = read(pipeFd[0], buf, sizeof buf);
    close(pipeFd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << seeds[s] << ": " << (WIFSIGNALED(status) ? "killed by signal " + std::to_string(WTERMSIG(status)) : "")
        << (got > 0 ? std::string(buf, static_cast<std::size_t>(got)) : std::string());
  }
}
