// `rabbit gaits build` (optimizers/gait_build.h): the shipped database is what the build makes from
// gaits/targets.toml (every file, byte for byte, and its manifest agrees with it), the search from
// Table 2 finds the two cheapest shipped gaits again byte for byte, the same bytes on 1 and 2
// threads, resume (an unchanged gait kept, a changed one rebuilt; the gaits of a build stopped
// after its synthesis taken by the next),
// a target that misses its criteria (nothing written for it), and the bad inputs: targets with
// the same name or (v_m, l_step), impossible bounds, unknown keys, reserved names, an --out that
// is not a database, a database whose manifest and files disagree (InputError, nothing written).
#include "gait_build.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli_fixture.h"
#include "gait_manifest.h"
#include "gait_targets.h"
#include "rabbit/gait/walker_settings.h"
#include "rabbit/io/error.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;
const std::string kRoot = RABBIT_SOURCE_DIR;

using testing::ReadText;

// The shipped targets of vm_0.30 and vm_0.40 (the cheapest: a few walks each), as in
// gaits/targets.toml but without their [gait.start]: the search from Table 2 finds them.
const char* const kTwoGaits = R"([[gait]]
v_m = 0.3
[gait.bounds]
qr1_dsw_deg = [10, 60]
q0_d_deg = [-5, 25]
pulse_torque_nm = [0, 100]
start_speed_m_s = [0.1, 1.5]
[gait.walker]
rule_share = 1

[[gait]]
v_m = 0.4
l_step = 0.24
)";

class GaitBuildTest : public testing::ScratchDirTest {
 protected:
  GaitBuildTest() : ScratchDirTest("rabbit_gait_build_test") {}
  GaitBuildResult Build(const std::string& targets, const std::string& out, int threads) {
    GaitBuildOptions options;
    options.out = (dir_ / out).string();
    options.threads = threads;
    return BuildGaitDatabase(ReadGaitTargets(targets), options);
  }
  void ExpectTargetsError(const std::string& text, int line, const std::string& key,
                          const std::string& fragment) {
    const std::string path = Write("bad.toml", text);
    try {
      ReadGaitTargets(path);
      ADD_FAILURE() << "no error for:\n" << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_EQ(e.key(), key) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
};

// Every file of gaits/ but README.md and the targets files is what `rabbit gaits build
// gaits/targets.toml` makes, and gaits/ holds nothing else: the gait files (speed gaits and
// library), their index, the networks, the fuzzy system, walker.csv and the manifest. The shipped
// manifest agrees with gaits/.
TEST_F(GaitBuildTest, TheShippedDatabaseIsWhatTheBuildMakes) {
  const fs::path shipped = kRoot + "/gaits";
  const Manifest manifest = ReadManifest((shipped / "manifest.csv").string());
  EXPECT_NO_THROW(VerifyManifest(manifest, shipped.string(), (shipped / "manifest.csv").string()));
  const GaitTargets targets = ReadGaitTargets((shipped / "targets.toml").string());
  const GaitBuildResult built = Build((shipped / "targets.toml").string(), "db", 2);
  EXPECT_EQ(built.exit_code(), 0) << ::testing::PrintToString(built.check_failures);
  // The eight speed gaits and the library cells.
  EXPECT_EQ(built.built.size(), targets.gaits.size());
  EXPECT_GT(targets.gaits.size(), 8u);
  EXPECT_TRUE(built.missed.empty()) << ::testing::PrintToString(built.missed);
  // Each gait is found at its start: one walk, and one more to record it; the two library gaits
  // that take fewer than 30 steps in 20 s (vm_0.50_l_0.34, vm_0.60_l_0.42) are recorded again
  // for the time of 31 steps.
  EXPECT_EQ(built.walks, 2 * static_cast<int>(targets.gaits.size()) + 2);
  auto files_of = [](const fs::path& root) {
    std::vector<std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(root)) {
      const fs::path rel = fs::relative(e.path(), root);
      if (!e.is_regular_file() || rel == "README.md" || rel.extension() == ".toml") continue;
      files.push_back(rel.generic_string());
    }
    std::sort(files.begin(), files.end());
    return files;
  };
  const std::vector<std::string> files = files_of(shipped);
  EXPECT_EQ(files, files_of(dir_ / "db"));
  EXPECT_EQ(files.size(), manifest.rows.size() + 1u);  // the manifest lists all but itself
  for (const std::string& file : files) {
    EXPECT_EQ(ReadText(dir_ / "db" / file), ReadText(shipped / file)) << file;
  }
}

TEST_F(GaitBuildTest, RebuildsShippedGaitsByteForByteWhateverTheThreads) {
  const std::string targets = Write("targets.toml", kTwoGaits);
  const GaitBuildResult one = Build(targets, "one", 1);
  EXPECT_EQ(one.exit_code(), 0);
  EXPECT_EQ(one.built, (std::vector<std::string>{"vm_0.30", "vm_0.40"}));
  for (const char* gait : {"vm_0.30", "vm_0.40"}) {
    const std::string file = std::string("reference/") + gait + ".csv";
    EXPECT_EQ(ReadText(dir_ / "one" / file), ReadText(kRoot + "/gaits/" + file)) << file;
  }
  const std::string manifest = ReadText(dir_ / "one" / "manifest.csv");
  EXPECT_EQ(manifest.rfind("# format = rabbit-gait-manifest/1\n", 0), 0u) << manifest;
  EXPECT_EQ(ReadWalkerSettings((dir_ / "one" / "walker.csv").string()).at("vm_0.30").rule_share,
            1.0);
  // Two threads: every file the same.
  Build(targets, "two", 2);
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "one")) {
    if (!e.is_regular_file()) continue;
    const fs::path rel = fs::relative(e.path(), dir_ / "one");
    files.push_back(rel.string());
    EXPECT_EQ(ReadText(e.path()), ReadText(dir_ / "two" / rel)) << rel;
  }
  // gaits, index, networks, their index and marker, fll, walker.csv, manifest
  EXPECT_EQ(files.size(), 2u + 1u + 8u + 1u + 1u + 1u + 1u + 1u);
  EXPECT_FALSE(fs::exists(dir_ / "one" / ".build"));
}

TEST_F(GaitBuildTest, ResumeKeepsUnchangedGaitsAndRebuildsChangedOnes) {
  const std::string targets = Write("targets.toml", kTwoGaits);
  Build(targets, "db", 1);
  const std::string manifest = ReadText(dir_ / "db" / "manifest.csv");
  GaitBuildResult again = Build(targets, "db", 1);
  EXPECT_TRUE(again.built.empty());
  EXPECT_EQ(again.kept.size(), 2u);
  EXPECT_EQ(ReadText(dir_ / "db" / "manifest.csv"), manifest);
  // An incomplete staging folder left by a killed build is dropped.
  fs::create_directories(dir_ / "db" / ".build" / "reference");
  std::ofstream(dir_ / "db" / ".build" / "reference" / "half.csv") << "x";
  EXPECT_EQ(Build(targets, "db", 1).kept.size(), 2u);
  EXPECT_FALSE(fs::exists(dir_ / "db" / ".build"));
  // A changed target (its seed) is rebuilt; the other is kept.
  std::string changed = kTwoGaits;
  changed += "seed = 2\n";
  const std::string targets2 = Write("targets2.toml", changed);
  again = Build(targets2, "db", 1);
  EXPECT_EQ(again.built, std::vector<std::string>{"vm_0.40"});
  EXPECT_EQ(again.kept, std::vector<std::string>{"vm_0.30"});
}

// A build that stops after its synthesis (here on a check suite whose scenario has a misspelt
// key, which only loading it on the new database finds) leaves the synthesized gaits in its
// staging folder; the next build of the folder takes those whose inputs and files are unchanged
// instead of synthesizing them, and writes the bytes of a build that never stopped.
TEST_F(GaitBuildTest, ABuildStoppedAfterItsSynthesisLeavesItsGaitsToTheNext) {
  Write("check.toml", "[suite]\nname = \"s\"\n[[scenario]]\nname = \"x\"\nduraton = 5\n");
  const std::string checked =
      Write("checked.toml", "[check]\nsuite = \"check.toml\"\n" + std::string(kTwoGaits));
  EXPECT_THROW(Build(checked, "db", 1), InputError);
  EXPECT_TRUE(fs::exists(dir_ / "db" / ".build" / "synthesized.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "db" / "manifest.csv"));
  const std::string targets = Write("targets.toml", kTwoGaits);
  const GaitBuildResult again = Build(targets, "db", 1);
  EXPECT_EQ(again.exit_code(), 0);
  EXPECT_EQ(again.reused, (std::vector<std::string>{"vm_0.30", "vm_0.40"}));
  EXPECT_EQ(again.built, again.reused);
  EXPECT_EQ(again.walks, 0);
  EXPECT_FALSE(fs::exists(dir_ / "db" / ".build"));
  Build(targets, "clean", 1);
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "clean")) {
    if (!e.is_regular_file()) continue;
    const fs::path rel = fs::relative(e.path(), dir_ / "clean");
    EXPECT_EQ(ReadText(dir_ / "db" / rel), ReadText(e.path())) << rel;
  }
  // A staged gait file that no longer has its listed hash is synthesized again, as is a gait
  // whose inputs changed (its seed); the other is taken.
  EXPECT_THROW(Build(checked, "db2", 1), InputError);
  std::ofstream(dir_ / "db2" / ".build" / "reference" / "vm_0.30.csv", std::ios::app) << "\n";
  GaitBuildResult r = Build(targets, "db2", 1);
  EXPECT_EQ(r.reused, std::vector<std::string>{"vm_0.40"});
  EXPECT_EQ(r.built, (std::vector<std::string>{"vm_0.30", "vm_0.40"}));
  EXPECT_GT(r.walks, 0);
  EXPECT_EQ(ReadText(dir_ / "db2" / "reference" / "vm_0.30.csv"),
            ReadText(dir_ / "clean" / "reference" / "vm_0.30.csv"));
  EXPECT_THROW(Build(checked, "db3", 1), InputError);
  r = Build(Write("seeded.toml", std::string(kTwoGaits) + "seed = 2\n"), "db3", 1);
  EXPECT_EQ(r.reused, std::vector<std::string>{"vm_0.30"});
  // The command says where the gaits stay, beside the error (exit 2).
  const fs::path err = dir_ / "err.txt";
  const std::string command = std::string(RABBIT_CLI_PATH) + " gaits build " + checked + " --out " +
                              (dir_ / "cli").string() + " -q -j1 2> " + err.string();
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  const std::string message = ReadText(err);
  EXPECT_NE(
      message.find("the gaits synthesized so far stay in " + (dir_ / "cli").string() + "/.build"),
      std::string::npos)
      << message;
  EXPECT_NE(message.find("check.toml:3"), std::string::npos) << message;
  // A folder refused before any work says nothing of gaits, whatever a .build in it holds.
  fs::create_directories(dir_ / "foreign" / ".build");
  std::ofstream(dir_ / "foreign" / "notes.txt") << "mine";
  std::ofstream(dir_ / "foreign" / ".build" / "synthesized.csv") << "x";
  const std::string refused = std::string(RABBIT_CLI_PATH) + " gaits build " + targets + " --out " +
                              (dir_ / "foreign").string() + " -q 2> " + err.string();
  const int code = std::system(refused.c_str());
  ASSERT_TRUE(WIFEXITED(code));
  EXPECT_EQ(WEXITSTATUS(code), 2);
  EXPECT_EQ(ReadText(err).find("stay in"), std::string::npos) << ReadText(err);
  EXPECT_EQ(ReadText(dir_ / "foreign" / "notes.txt"), "mine");
}

TEST_F(GaitBuildTest, MissedTargetExitsOneAndWritesNothingForIt) {
  const std::string targets = Write(
      "targets.toml", std::string(kTwoGaits) + "[[gait]]\nv_m = 0.9\nl_step = 0.47\nbudget = 1\n");
  const GaitBuildResult r = Build(targets, "db", 2);
  EXPECT_EQ(r.exit_code(), 1);
  EXPECT_EQ(r.missed, std::vector<std::string>{"vm_0.90"});
  EXPECT_FALSE(fs::exists(dir_ / "db" / "reference" / "vm_0.90.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "db" / "networks" / "vm_0.90_q_i1.csv"));
  EXPECT_TRUE(fs::exists(dir_ / "db" / "reference" / "vm_0.40.csv"));
  EXPECT_EQ(ReadText(dir_ / "db" / "manifest.csv").find("vm_0.90"), std::string::npos);
}

TEST_F(GaitBuildTest, RefusesAnOutThatIsNotADatabaseOrDisagreesWithItsManifest) {
  const std::string targets = Write("targets.toml", kTwoGaits);
  fs::create_directories(dir_ / "other");
  std::ofstream(dir_ / "other" / "notes.txt") << "mine\n";
  EXPECT_THROW(Build(targets, "other", 1), InputError);
  EXPECT_EQ(ReadText(dir_ / "other" / "notes.txt"), "mine\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_ / "other"), fs::directory_iterator()), 1);
  // A database whose gait file was edited: refused, untouched.
  Build(targets, "db", 1);
  std::ofstream(dir_ / "db" / "reference" / "vm_0.40.csv", std::ios::app) << "\n";
  const std::string edited = ReadText(dir_ / "db" / "reference" / "vm_0.40.csv");
  try {
    Build(targets, "db", 1);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "reference/vm_0.40.csv") << e.what();
  }
  EXPECT_EQ(ReadText(dir_ / "db" / "reference" / "vm_0.40.csv"), edited);
  // A file the manifest does not list.
  fs::resize_file(dir_ / "db" / "reference" / "vm_0.40.csv", edited.size() - 1);
  std::ofstream(dir_ / "db" / "reference" / "extra.csv") << "x\n";
  EXPECT_THROW(Build(targets, "db", 1), InputError);
}

// A manifest row naming a file the file system cannot even look up (a name longer than its 255-byte
// limit) is a bad manifest (InputError naming the row's file), not a file-system exception.
TEST_F(GaitBuildTest, AManifestRowWithANameTooLongForTheFileSystemIsAnInputError) {
  const std::string name = std::string(300, 'g') + ".csv";
  const std::string manifest = Write(
      "manifest.csv", "# format = rabbit-gait-manifest/1\nkind,name,file,sha256,seed,inputs_sha256\n"
                      "file,," + name + "," + std::string(64, '0') + ",,\n");
  fs::create_directories(dir_ / "db");
  try {
    VerifyManifest(ReadManifest(manifest), (dir_ / "db").string(), manifest);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), name);
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos) << e.what();
  }
}

TEST_F(GaitBuildTest, BadTargetsNameFileLineAndKey) {
  ExpectTargetsError("[[gait]]\nv_m = 0.4\n[[gait]]\nv_m = 0.5\nname = \"vm_0.40\"\n", 5,
                     "gait[2].name", "second target named");
  ExpectTargetsError(
      "[[gait]]\nv_m = 0.4\nl_step = 0.2\n[[gait]]\nv_m = 0.4\nl_step = 0.2\nname = \"b\"\n", 5,
      "gait[2].v_m", "same (v_m, l_step)");
  ExpectTargetsError("[[gait]]\nv_m = 0.4\n[gait.bounds]\nhip_kp = [100, 50]\n", 4,
                     "gait[1].bounds.hip_kp", "lower < upper");
  ExpectTargetsError("[[gait]]\nv_m = 0.4\nspeed = 3\n", 3, "gait[1].speed", "");
  ExpectTargetsError("[[gait]]\nv_m = 0.4\n[gait.walker]\nrule_shares = 1\n", 4,
                     "gait[1].walker.rule_shares", "");
  ExpectTargetsError("[[gait]]\nv_m = 0.4\n[gait.walker]\nrule_share = 2\n", 4,
                     "gait[1].walker.rule_share", "[0, 1]");
  // A start outside its bounds (the target's, over the defaults), or of an unknown parameter.
  ExpectTargetsError("[[gait]]\nv_m = 0.4\n[gait.start]\nq0_d_deg = 20\n", 4,
                     "gait[1].start.q0_d_deg", "within its bounds [-5, 15]");
  ExpectTargetsError("[[gait]]\nv_m = 0.4\n[gait.start]\nq0_d = 2\n", 4, "gait[1].start.q0_d",
                     "q0_d_deg");
  ExpectTargetsError("[[gait]]\nv_m = 0.4\nname = \"index\"\n", 3, "gait[1].name",
                     "database's own files");
  ExpectTargetsError("[[gait]]\nv_m = 0.4\nname = \"manifest\"\n", 3, "gait[1].name",
                     "database's own files");
}

// The command: bad targets exit 2 naming the file and key, and write nothing.
// The check suite runs on the built database, but its file is read first: a missing, broken or
// wrong one is named at the targets' `check.suite`, before any work, and nothing is written.
TEST_F(GaitBuildTest, TheCheckSuiteIsReadBeforeTheWork) {
  Write("suite.toml", "[suite]\nname = \"s\"\n");
  Write("job.toml", "[job]\nsuites = [\"suite.toml\"]\n");
  Write("broken.toml", "[suite\n");
  const std::string job = (dir_ / "job.toml").string();
  for (const auto& [suite, message] :
       {std::pair<std::string, std::string>{
            "none.toml", (dir_ / "none.toml").string() + ": cannot open the file: no such file"},
        {"job.toml", job + ": this is a tuning job, not a scenario or a suite: run it with "
                           "`rabbit tune`"},
        {"broken.toml", (dir_ / "broken.toml").string() + ":1"}}) {
    SCOPED_TRACE(suite);
    const std::string targets =
        Write("targets.toml", "[check]\nsuite = \"" + suite + "\"\n" + kTwoGaits);
    try {
      Build(targets, "db", 1);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(targets + ":2: 'check.suite': " + message, 0), 0u)
          << e.what();
    }
    EXPECT_FALSE(fs::exists(dir_ / "db"));
  }
}

TEST_F(GaitBuildTest, CommandExitsTwoOnBadTargetsAndWritesNothing) {
  const std::string bad = Write("bad.toml", "[[gait]]\nv_m = 0.4\nname = \"index\"\n");
  const fs::path out = dir_ / "out";
  const fs::path err = dir_ / "err.txt";
  const std::string command = std::string(RABBIT_CLI_PATH) + " gaits build " + bad + " --out " +
                              out.string() + " -q 2> " + err.string();
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  EXPECT_FALSE(fs::exists(out));
  const std::string message = ReadText(err);
  EXPECT_NE(message.find("bad.toml:3"), std::string::npos) << message;
  EXPECT_NE(message.find("gait[1].name"), std::string::npos) << message;
}

TEST(WalkerSettingsTest, RoundTripAndBadFiles) {
  const fs::path dir = fs::temp_directory_path() / ("rabbit_walker_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "walker.csv").string();
  WriteWalkerSettings({{"a", {1.0}}, {"b", {0.25}}}, path);
  const auto back = ReadWalkerSettings(path);
  EXPECT_EQ(back.at("a").rule_share, 1.0);
  EXPECT_EQ(back.at("b").rule_share, 0.25);
  std::ofstream(path) << "name,rule_share,gain\na,1,2\n";
  EXPECT_THROW(ReadWalkerSettings(path), InputError);
  std::ofstream(path) << "name,rule_share\na,1\na,0\n";
  try {
    ReadWalkerSettings(path);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.key(), "name");
  }
  std::ofstream(path) << "name,rule_share\na,1.5\n";
  EXPECT_THROW(ReadWalkerSettings(path), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rabbit
