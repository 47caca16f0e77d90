// The CSV gait database: round trip, and every kind of malformed file refused with an InputError
// naming the file and line.
#include "rabbit/gait/gait_database.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "rabbit/io/error.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

GaitRecord SampleGait() {
  GaitRecord g;
  g.name = "vm_0.55";
  g.target_v_m = 0.55;
  g.target_l_step = 0.32;
  g.measured.v_m = 0.551;
  g.measured.l_step = 0.318;
  g.measured.t_step = 0.577;
  g.measured.steps = 31;
  g.spec.rules.qr1_dsw = 0.5;
  g.spec.start_speed = 0.5;
  g.model_hash = ModelHash(ModelParams{});
  g.source = "test";
  g.seed = 7;
  for (int i = 0; i < 5; ++i) g.swing.push_back({-0.3 + 0.1 * i, 0.1 * i, -0.2, 1.0, -0.5 * i});
  return g;
}

class GaitDatabaseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_gait_db_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // The sample gait's file with `from` replaced by `to`.
  std::string Tampered(const std::string& from, const std::string& to) {
    const std::string good = (dir_ / "good.csv").string();
    WriteGaitFile(SampleGait(), good);
    std::ifstream in(good);
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    s.replace(at, from.size(), to);
    const std::string bad = (dir_ / "bad.csv").string();
    std::ofstream(bad) << s;
    return bad;
  }
  void ExpectRefused(const std::string& path, int line, const std::string& fragment) {
    try {
      ReadGaitFile(path);
      ADD_FAILURE() << "accepted " << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      if (line > 0) {
        EXPECT_EQ(e.line(), line) << e.what();
      }
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
  fs::path dir_;
};

TEST_F(GaitDatabaseTest, RoundTrip) {
  const GaitRecord g = SampleGait();
  const std::string path = AddGaitToDatabase(g, dir_.string());
  const GaitRecord r = ReadGaitFile(path);
  EXPECT_EQ(r.name, g.name);
  EXPECT_EQ(r.model_hash, g.model_hash);
  EXPECT_EQ(r.seed, 7u);
  EXPECT_NEAR(r.spec.rules.qr1_dsw, 0.5, 1e-9);
  EXPECT_NEAR(r.measured.v_m, 0.551, 1e-9);
  ASSERT_EQ(r.swing.size(), g.swing.size());
  for (size_t i = 0; i < g.swing.size(); ++i) {
    EXPECT_NEAR(r.swing[i].e, g.swing[i].e, 1e-11);
    EXPECT_NEAR(r.swing[i].qd2, g.swing[i].qd2, 1e-11);
  }
  const std::vector<GaitIndexEntry> index = ReadGaitIndex((dir_ / "index.csv").string());
  ASSERT_EQ(index.size(), 1u);
  EXPECT_EQ(index[0].file, "vm_0.55.csv");
  // Adding it again replaces its row.
  AddGaitToDatabase(g, dir_.string());
  EXPECT_EQ(ReadGaitIndex((dir_ / "index.csv").string()).size(), 1u);
}

TEST_F(GaitDatabaseTest, MalformedFilesAreRefusedWithFileAndLine) {
  ExpectRefused(Tampered("format = rabbit-gait/1", "format = rabbit-gait/9"), 1,
                "unsupported format");
  ExpectRefused(Tampered("# format = rabbit-gait/1\n", ""), 1, "missing '# format");
  ExpectRefused(Tampered(",qd_i2_rad_s", ""), 0, "missing column");
  ExpectRefused(Tampered("e_rad,q_i1_rad", "e_rad,q_hip_rad"), 0, "missing column");
  ExpectRefused(Tampered("-0.2,0.1,", "-0.2,nan,"), 0, "number");
  ExpectRefused(Tampered("-0.1,0.2,", "-0.35,0.2,"), 0, "increase");
  ExpectRefused(Tampered("# q0_d_deg", "# q0_deg"), 0, "q0_d_deg");
  ExpectRefused((dir_ / "missing.csv").string(), 0, "cannot open");
}

TEST_F(GaitDatabaseTest, ErrorLinesPointAtTheRow) {
  const std::string path = Tampered("-0.1,0.2,", "-0.1,oops,");
  try {
    ReadGaitFile(path);
    FAIL();
  } catch (const InputError& e) {
    // The row of e = -0.1 is the 3rd data row, after the metadata and the header.
    std::ifstream in(path);
    std::string line;
    int n = 0, row = 0;
    while (std::getline(in, line)) {
      ++n;
      if (line.rfind("-0.1,", 0) == 0) row = n;
    }
    EXPECT_EQ(e.line(), row);
    EXPECT_EQ(e.key(), "q_i1_rad");
  }
}

TEST_F(GaitDatabaseTest, RolesRoundTripAndSpeedGaitsComeFirst) {
  GaitRecord speed = SampleGait();
  GaitRecord library = SampleGait();
  library.name = "vm_0.40_l_0.20";
  library.role = GaitRole::kLibrary;
  library.target_v_m = 0.4;  // slower than the speed gait: still listed after it
  library.target_l_step = 0.2;
  GaitRecord faster = SampleGait();
  faster.name = "vm_0.70";
  faster.target_v_m = 0.7;
  AddGaitToDatabase(library, dir_.string());
  AddGaitToDatabase(faster, dir_.string());
  AddGaitToDatabase(speed, dir_.string());
  const std::vector<GaitIndexEntry> index = ReadGaitIndex((dir_ / "index.csv").string());
  ASSERT_EQ(index.size(), 3u);
  EXPECT_EQ(index[0].name, "vm_0.55");
  EXPECT_EQ(index[1].name, "vm_0.70");
  EXPECT_EQ(index[2].name, "vm_0.40_l_0.20");
  EXPECT_EQ(index[2].role, GaitRole::kLibrary);
  EXPECT_EQ(index[2].target_l_step, 0.2);
  EXPECT_EQ(index[0].role, GaitRole::kSpeed);
  EXPECT_EQ(index[0].target_l_step, 0.32);
  EXPECT_EQ(GaitsOfRole(index, GaitRole::kSpeed).size(), 2u);
  EXPECT_EQ(GaitsOfRole(index, GaitRole::kLibrary).size(), 1u);
  EXPECT_EQ(ReadGaitFile((dir_ / "vm_0.40_l_0.20.csv").string()).role, GaitRole::kLibrary);
  // A speed gait's file has no role line (its bytes are those of a file without roles).
  std::ifstream in(dir_ / "vm_0.55.csv");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str().find("# role"), std::string::npos);
  EXPECT_EQ(ReadGaitFile((dir_ / "vm_0.55.csv").string()).role, GaitRole::kSpeed);
}

TEST_F(GaitDatabaseTest, AnIndexWithoutRolesListsSpeedGaits) {
  const std::string path = (dir_ / "index.csv").string();
  std::ofstream(path) << "name,file,target_v_m,measured_v_m,l_step_m,t_step_s,steps,source\n"
                      << "vm_0.60,vm_0.60.csv,0.6,0.58,0.35,0.6,32,test\n";
  const std::vector<GaitIndexEntry> index = ReadGaitIndex(path);
  ASSERT_EQ(index.size(), 1u);
  EXPECT_EQ(index[0].role, GaitRole::kSpeed);
  EXPECT_EQ(index[0].target_l_step, 0.0);
}

TEST_F(GaitDatabaseTest, AnUnknownRoleIsRefused) {
  ExpectRefused(Tampered("# source = test\n", "# source = test\n# role = sprint\n"), 0,
                "unknown role");
  const std::string path = (dir_ / "index.csv").string();
  std::ofstream(path)
      << "name,file,target_v_m,measured_v_m,l_step_m,t_step_s,steps,source,role,target_l_step_m\n"
      << "vm_0.60,vm_0.60.csv,0.6,0.58,0.35,0.6,32,test,sprint,0.3\n";
  try {
    ReadGaitIndex(path);
    ADD_FAILURE() << "accepted an unknown role";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.key(), "role");
  }
}

}  // namespace
}  // namespace rabbit
