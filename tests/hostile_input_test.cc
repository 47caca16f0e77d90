// Hostile input, end to end: one row per class of bad input and per reader, each run through the
// built `rabbit` binary in a scratch folder. Every row states the command, the exit code, the
// fragments its message must hold (the file or flag or key, and the limit or range), the files
// that must be left byte for byte as they were and the outputs that must not appear. Unbounded
// input is a large sparse file or a FIFO fed by a writer thread with a bounded amount of data
// (never a system device). No sleeps: the FIFO's writer is released by opening the FIFO.
#include <gtest/gtest.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "hostile_fixture.h"

// The table's rows leave their optional fields (untouched, absent, fifo) out.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace {

namespace fs = std::filesystem;
using rabbit::testing::Case;
using rabbit::testing::CliRun;
using rabbit::testing::Expand;
using rabbit::testing::FifoWriter;
using rabbit::testing::kDrop;
using rabbit::testing::kDropInSuite;
using rabbit::testing::kMiB;
using rabbit::testing::ReadText;
using rabbit::testing::Replace;
using rabbit::testing::RunCli;
using rabbit::testing::ScenarioText;
using rabbit::testing::Snapshot;
using rabbit::testing::Sparse;
using rabbit::testing::WalkerScenario;
using rabbit::testing::WriteText;

const std::string kRoot = RABBIT_SOURCE_DIR;

std::vector<Case> Cases() {
  std::vector<Case> c;
  // ---- Unbounded input: every reader stops at its limit, naming the file and the limit. ----
  c.push_back({"gait index from a FIFO (as /dev/zero)",
               [](const fs::path& d) { fs::create_directories(d / "g"); },
               "gaits list --dir {D}/g",
               2,
               {"{D}/g/index.csv", "larger than 4 MiB", "index files"},
               {},
               {},
               "g/index.csv",
               6 * kMiB});
  c.push_back({"FLL from a FIFO (as /dev/zero)",
               [](const fs::path&) {},
               "fis eval {D}/p.fll --vm 0.5",
               2,
               {"{D}/p.fll", "larger than 4 MiB", "FLL files"},
               {},
               {},
               "p.fll",
               5 * kMiB});
  c.push_back({"CSV table: a 1 GB summary.csv",
               [](const fs::path& d) {
                 WriteText(d / "rep/.rabbit-report", "rabbit-report/1\n");
                 Sparse(d / "rep/summary.csv", 1000000000);
               },
               "report {D}/rep",
               2,
               {"{D}/rep/summary.csv", "larger than 768 MiB", "CSV files"},
               {},
               {"{D}/rep/index.html"}});
  c.push_back({"gait CSV: 20 MB",
               [](const fs::path& d) {
                 Sparse(d / "big.csv", 20 * kMiB);
                 WriteText(d / "s.toml", ScenarioText("p",
                                                      "[simulation]\nduration = 1\n"
                                                      "[controller]\ntype = \"pragmatic\"\n"
                                                      "gait = \"big.csv\"\n"));
               },
               "simulate {D}/s.toml --out {D}/t.csv",
               2,
               {"{D}/big.csv", "larger than 16 MiB", "gait files"},
               {"{D}/s.toml"},
               {"{D}/t.csv"}});
  c.push_back({"network index: 5 MB",
               [](const fs::path& d) { Sparse(d / "n/index.csv", 5 * kMiB); },
               "fis eval {R}/gaits/gait_pattern.fll --vm 0.5 --e-deg 10 --networks {D}/n",
               2,
               {"{D}/n/index.csv", "larger than 4 MiB"}});
  c.push_back({"network CSV: 300 MB",
               [](const fs::path& d) {
                 fs::copy(kRoot + "/gaits/networks", d / "n");
                 Sparse(d / "n/vm_0.30_q_i1.csv", 300 * kMiB);
               },
               "fis eval {R}/gaits/gait_pattern.fll --vm 0.5 --e-deg 10 --networks {D}/n",
               2,
               {"{D}/n/vm_0.30_q_i1.csv", "larger than 256 MiB", "network files"}});
  c.push_back({"FLL: one 100 kB line",
               [](const fs::path& d) { WriteText(d / "l.fll", std::string(100000, 'x')); },
               "fis eval {D}/l.fll --vm 0.5",
               2,
               {"{D}/l.fll:1", "line longer than 64 KiB"}});
  for (const auto& [what, args] : std::vector<std::pair<std::string, std::string>>{
           {"scenario", "simulate {D}/big.toml --out {D}/out"},
           {"suite", "run {D}/big.toml --out {D}/out"},
           {"tuning job", "tune {D}/big.toml --out {D}/out"},
           {"gait targets", "gaits generate {D}/big.toml --dir {D}/out"},
           {"overlay",
            "simulate {R}/scenarios/drop_2cm.toml --params {D}/big.toml --out {D}/out"}}) {
    c.push_back({"TOML " + what + ": 5 MB",
                 [](const fs::path& d) { Sparse(d / "big.toml", 5 * kMiB); },
                 args,
                 2,
                 {"{D}/big.toml", "larger than 4 MiB", "TOML files"},
                 {},
                 {"{D}/out"}});
  }
  c.push_back({"TOML model file: 5 MB",
               [](const fs::path& d) {
                 Sparse(d / "m.toml", 5 * kMiB);
                 WriteText(d / "s.toml", ScenarioText("m", "[model]\nfile = \"m.toml\"\n" + kDrop));
               },
               "simulate {D}/s.toml --out {D}/t.csv",
               2,
               {"{D}/m.toml", "larger than 4 MiB"},
               {},
               {"{D}/t.csv"}});
  c.push_back({"TOML: more than 100000 lines",
               [](const fs::path& d) { WriteText(d / "s.toml", std::string(100001, '\n')); },
               "simulate {D}/s.toml",
               2,
               {"{D}/s.toml:100001", "more than 100000 lines"}});

  // ---- Nonsense values: refused with the key or flag and the range. ----
  c.push_back({"record_every = 0",
               [](const fs::path& d) {
                 WriteText(d / "s.toml",
                           ScenarioText("r",
                                        "[simulation]\nduration = 0.05\nrecord_every = 0\n"
                                        "[initial]\nfoot_clearance = 0.02\n"));
               },
               "simulate {D}/s.toml --out {D}/t.csv",
               2,
               {"{D}/s.toml:4", "'simulation.record_every'", "[1, 1000000]"},
               {},
               {"{D}/t.csv"}});
  c.push_back({"duration = 99000",
               [](const fs::path& d) {
                 WriteText(d / "s.toml", ScenarioText("d",
                                                      "[simulation]\nduration = 99000\n"
                                                      "[initial]\nfoot_clearance = 0.02\n"));
               },
               "simulate {D}/s.toml --out {D}/t.csv",
               2,
               {"{D}/s.toml:3", "'simulation.duration'", "[0, 3600] s"},
               {},
               {"{D}/t.csv"}});
  c.push_back({"more samples than kept",
               [](const fs::path& d) {
                 WriteText(d / "s.toml", ScenarioText("d",
                                                      "[simulation]\nduration = 3000\n"
                                                      "control_rate_hz = 1000\n"
                                                      "[initial]\nfoot_clearance = 0.02\n"));
               },
               "simulate {D}/s.toml --out {D}/t.csv",
               2,
               {"'simulation.record_every'", "more than 1e+06 samples"},
               {},
               {"{D}/t.csv"}});
  c.push_back({"--family-details -2 (run)",
               [](const fs::path&) {},
               "run {R}/scenarios/paper.toml --family-details -2 --out {D}/out",
               2,
               {"--family-details", "[-1, 100000]", "\"-2\""},
               {},
               {"{D}/out"}});
  c.push_back({"--family-details -2 (report)",
               [](const fs::path& d) { fs::create_directories(d / "rep"); },
               "report {D}/rep --family-details -2",
               2,
               {"--family-details", "[-1, 100000]"}});
  c.push_back({"fis eval --vm 1e308",
               [](const fs::path&) {},
               "fis eval --vm 1e308",
               2,
               {"--vm", "[-5, 5] m/s", "1e308"}});
  c.push_back({"fis eval --vm \"\"",
               [](const fs::path&) {},
               "fis eval --vm ''",
               2,
               {"--vm", "expected a number", "got \"\""}});
  c.push_back({"fis eval --e-deg nan",
               [](const fs::path&) {},
               "fis eval --vm 0.5 --e-deg nan",
               2,
               {"--e-deg", "[-180, 180] deg"}});
  c.push_back({"search bounds [-1000, -999] deg",
               [](const fs::path& d) {
                 WriteText(d / "t.toml",
                           "[[gait]]\nv_m = 0.5\n[gait.bounds]\n"
                           "q0_d_deg = [-1000, -999]\n");
               },
               "gaits generate {D}/t.toml --dir {D}/out",
               2,
               {"{D}/t.toml:4", "q0_d_deg", "within [-45, 45]"},
               {"{D}/t.toml"},
               {"{D}/out"}});
  c.push_back({"two targets for one gait",
               [](const fs::path& d) {
                 WriteText(d / "t.toml", "[[gait]]\nv_m = 0.5\n[[gait]]\nv_m = 0.501\n");
               },
               "gaits generate {D}/t.toml --dir {D}/out",
               2,
               {"{D}/t.toml:3", "'gait[2].name'", "vm_0.50"},
               {},
               {"{D}/out"}});
  c.push_back({"network index: q_i1 pointing at the q_i2 file",
               [](const fs::path& d) {
                 fs::copy(kRoot + "/gaits/networks", d / "n");
                 Replace(d / "n/index.csv", "vm_0.30,q_i1,vm_0.30_q_i1.csv",
                         "vm_0.30,q_i1,vm_0.30_q_i2.csv");
               },
               "fis eval {R}/gaits/gait_pattern.fll --vm 0.5 --e-deg 10 --networks {D}/n",
               2,
               {"{D}/n/index.csv:2", "'output'", "says \"q_i2\""},
               {"{D}/n"}});
  c.push_back({"network index: header lacks columns",
               [](const fs::path& d) {
                 fs::copy(kRoot + "/gaits/networks", d / "n");
                 Replace(d / "n/index.csv", "gait,output,file,method,rms,weights", "gait,output");
               },
               "fis eval {R}/gaits/gait_pattern.fll --vm 0.5 --e-deg 10 --networks {D}/n",
               2,
               {"{D}/n/index.csv:1", "expected the header row"},
               {"{D}/n"}});
  // A duplicated gait row: refused by every command that reads the index.
  const auto duplicate = [](const fs::path& d) {
    fs::copy(kRoot + "/gaits/reference", d / "g");
    std::string text = ReadText(d / "g/index.csv");
    // The first gait's row again, right below it (line 3), whatever the database's size.
    const size_t second = text.find('\n') + 1;
    text.insert(second, text.substr(second, text.find('\n', second) + 1 - second));
    WriteText(d / "g/index.csv", text);
    WriteText(d / "s.toml", WalkerScenario((d / "g").string(), ""));
  };
  const std::vector<std::string> twice = {"{D}/g/index.csv:3", "'name'", "listed twice",
                                          "first on line 2"};
  c.push_back({"duplicated gait row: gaits list",
               duplicate,
               "gaits list --dir {D}/g",
               2,
               twice,
               {"{D}/g"}});
  c.push_back({"duplicated gait row: train",
               duplicate,
               "train --gaits {D}/g --out {D}/nets",
               2,
               twice,
               {"{D}/g"},
               {"{D}/nets"}});
  c.push_back({"duplicated gait row: fis generate",
               duplicate,
               "fis generate --gaits {D}/g --out {D}/p.fll",
               2,
               twice,
               {"{D}/g"},
               {"{D}/p.fll"}});
  c.push_back({"duplicated gait row: simulate",
               duplicate,
               "simulate {D}/s.toml --out {D}/t.csv",
               2,
               twice,
               {"{D}/g"},
               {"{D}/t.csv"}});
  c.push_back({"duplicated gait row: gaits report",
               duplicate,
               "gaits report --dir {D}/g --out {D}/rep",
               2,
               twice,
               {"{D}/g"},
               {"{D}/rep"}});
  c.push_back({"gait index: header lacks columns",
               [](const fs::path& d) {
                 fs::copy(kRoot + "/gaits/reference", d / "g");
                 Replace(d / "g/index.csv", "name,file,target_v_m,measured_v_m,", "name,file,");
               },
               "gaits list --dir {D}/g",
               2,
               {"{D}/g/index.csv:1", "expected the header row"},
               {"{D}/g"}});
  c.push_back({"gait index: empty",
               [](const fs::path& d) { WriteText(d / "g/index.csv", ""); },
               "gaits list --dir {D}/g",
               2,
               {"{D}/g/index.csv", "empty file"}});
  c.push_back({"gait file: a metadata key given twice",
               [](const fs::path& d) {
                 fs::copy(kRoot + "/gaits/reference/vm_0.60.csv", d / "g.csv");
                 Replace(d / "g.csv", "# measured_v_m", "# hip_kp = 1\n# measured_v_m");
                 WriteText(d / "s.toml", ScenarioText("p",
                                                      "[simulation]\nduration = 1\n"
                                                      "[controller]\ntype = \"pragmatic\"\n"
                                                      "gait = \"g.csv\"\n"));
               },
               "simulate {D}/s.toml --out {D}/t.csv",
               2,
               {"{D}/g.csv:", "'hip_kp'", "given twice"},
               {"{D}/g.csv"},
               {"{D}/t.csv"}});

  // ---- Errors that used to name nothing. ----
  c.push_back({"fll = \"\"",
               [](const fs::path& d) {
                 WriteText(d / "s.toml", WalkerScenario(kRoot + "/gaits/reference", ""));
                 Replace(d / "s.toml", "fll = \"" + kRoot + "/gaits/gait_pattern.fll\"",
                         "fll = \"\"");
               },
               "simulate {D}/s.toml --out {D}/t.csv",
               2,
               {"{D}/s.toml:", "'controller.fll'", "empty path"},
               {},
               {"{D}/t.csv"}});
  c.push_back({"gait step lengths not distinct (step planner)",
               [](const fs::path& d) {
                 fs::copy(kRoot + "/gaits/reference", d / "g");
                 // vm_0.40 given vm_0.30's measured step length.
                 auto l_step_line = [&d](const char* gait) {
                   const std::string text = ReadText(d / "g" / gait);
                   const size_t at = text.find("# measured_l_step_m = ");
                   return text.substr(at, text.find('\n', at) - at);
                 };
                 Replace(d / "g/vm_0.40.csv", l_step_line("vm_0.40.csv"),
                         l_step_line("vm_0.30.csv"));
                 WriteText(d / "s.toml", WalkerScenario((d / "g").string(),
                                                        "[controller.planner]\nenabled = true\n"));
               },
               "simulate {D}/s.toml --out {D}/t.csv",
               2,
               {"{D}/g/index.csv", "measured_l_step_m", "must be distinct", "{D}/s.toml"},
               {"{D}/g"},
               {"{D}/t.csv"}});
  c.push_back({"a 10 kB suite name",
               [](const fs::path& d) {
                 WriteText(d / "s.toml", "[suite]\nname = \"" + std::string(10240, 'a') +
                                             "\"\n[[scenario]]\nname = \"x\"\n" + kDropInSuite);
               },
               "run {D}/s.toml --out {D}/out",
               2,
               {"{D}/s.toml", "'suite.name'", "1 to 100", "got 10240 characters"},
               {"{D}/s.toml"},
               {"{D}/out"}});
  c.push_back({"a 10 kB gait name (--name)",
               [](const fs::path&) {},
               "gaits synthesize --vm 0.5 --name " + std::string(10240, 'a') + " --dir {D}/g",
               2,
               {"--name", "1 to 100", "got 10240 characters"},
               {},
               {"{D}/g"}});
  c.push_back({"unknown bound key",
               [](const fs::path& d) {
                 WriteText(d / "t.toml", "[[gait]]\nv_m = 0.5\n[gait.bounds]\nfoo_deg = [1, 2]\n");
               },
               "gaits generate {D}/t.toml --dir {D}/out",
               2,
               {"{D}/t.toml:4", "'gait[1].bounds.foo_deg'", "expected one of: hip_kd"},
               {},
               {"{D}/out"}});

  // ---- Terrain steps, event-timed pushes, family draws: bad values named by file and key. ----
  struct KeyRow {
    const char* name;
    const char* body;  // after a drop scenario's keys (line 10 on)
    const char* where;
    const char* key;
    const char* fragment;
  };
  const KeyRow key_rows[] = {
      {"terrain step rise = 0", "[[terrain.steps]]\nx_start = 1.0\nrise = 0.0\n", "{D}/s.toml:12",
       "'terrain.steps[1].rise'", "nonzero and within +-1 m"},
      {"terrain steps out of order",
       "[[terrain.steps]]\nx_start = 1.0\nrise = 0.02\n[[terrain.steps]]\nx_start = 0.5\n"
       "rise = -0.02\n",
       "{D}/s.toml:14", "'terrain.steps[2].x_start'", "increasing x_start"},
      {"terrain step with slope_deg",
       "[terrain]\nslope_deg = 2.0\n[[terrain.steps]]\nx_start = 1.0\nrise = 0.02\n",
       "{D}/s.toml:13", "'terrain.steps[1].x_start'", "uniform slope_deg"},
      {"push with start and after_touchdown", "[[push]]\nstart = 1.0\nafter_touchdown = 3\n",
       "{D}/s.toml:11", "'push[1].start'", "not both"},
      {"push after_touchdown = 0", "[[push]]\nafter_touchdown = 0\n", "{D}/s.toml:11",
       "'push[1].after_touchdown'", "[1, 100000]"},
      {"push phase = 1.5", "[[push]]\nafter_touchdown = 3\nphase = 1.5\n", "{D}/s.toml:12",
       "'push[1].phase'", "[0, 1]"},
      {"push phase without a touchdown", "[[push]]\nat_hip_x = 2.0\nphase = 0.5\n", "{D}/s.toml:12",
       "'push[1].phase'", "after_touchdown"},
      {"push impulse and force", "[[push]]\nstart = 0.0\nimpulse_n_s = 5.0\nforce_x = 3.0\n",
       "{D}/s.toml:12", "'push[1].impulse_n_s'", "not both"},
      {"push duration = 0", "[[push]]\nstart = 0.0\nduration = 0.0\nimpulse_n_s = 5.0\n",
       "{D}/s.toml:12", "'push[1].duration'", "> 0 s"},
  };
  for (const KeyRow& row : key_rows) {
    const std::string body = row.body;
    c.push_back({row.name,
                 [body](const fs::path& d) {
                   WriteText(d / "s.toml",
                             ScenarioText("k",
                                          "[simulation]\nduration = 0.05\n[initial]\n"
                                          "foot_clearance = 0.02\n[controller]\n"
                                          "type = \"pd_hold\"\nkp = 600.0\nkd = 30.0\n" +
                                              body));
                 },
                 "simulate {D}/s.toml --out {D}/t.csv",
                 2,
                 {row.where, row.key, row.fragment},
                 {},
                 {"{D}/t.csv"}});
  }
  struct FamilyRow {
    const char* name;
    const char* body;  // the family's tables (line 5 on)
    const char* where;
    const char* key;
    const char* fragment;
  };
  const FamilyRow family_rows[] = {
      {"family draw with a bad name", "[family.draw]\n\"a b\" = [0, 1]\n", "{D}/s.toml:7",
       "'family[1].draw.a b'", "a draw's name"},
      {"family expression with an unknown name",
       "[[family.scenario.push]]\nstart = 1.0\n[family.vary]\n\"push.1.start\" = \"=t0 + 1\"\n",
       "{D}/s.toml:9", "'family[1].vary.push.1.start'", "'t0' names no draw"},
      {"family expression dividing by zero",
       "[[family.scenario.push]]\nstart = 1.0\n[family.draw]\nz = [0, 0]\n[family.vary]\n"
       "\"push.1.start\" = \"=1 / z\"\n",
       "{D}/s.toml:11", "'family[1].vary.push.1.start'", "division by zero"},
      {"family draws in a circle", "[family.draw]\na = \"=b\"\nb = \"=a\"\n", "{D}/s.toml:7",
       "'family[1].draw.a'", "in a circle"},
      {"family velocity.changes count = 200",
       "[family.vary]\n\"velocity.changes\" = { count = 200, every_s = 5, v = 0.5 }\n",
       "{D}/s.toml:7", "'family[1].vary.velocity.changes.count'", "[0, 100]"},
      {"family integer key drawn as a real",
       "[[family.scenario.push]]\nafter_touchdown = 3\n[family.vary]\n"
       "\"push.1.after_touchdown\" = [2, 5]\n",
       "{D}/s.toml:9", "'family[1].vary.push.1.after_touchdown'", "integer = true"},
  };
  for (const FamilyRow& row : family_rows) {
    const std::string body = row.body;
    c.push_back({row.name,
                 [body](const fs::path& d) {
                   WriteText(d / "s.toml",
                             "[suite]\nname = \"h\"\n[[family]]\nname = \"f\"\ncount = 2\n" + body);
                 },
                 "run {D}/s.toml --out {D}/out",
                 2,
                 {row.where, row.key, row.fragment},
                 {},
                 {"{D}/out"}});
  }

  // ---- User regular expressions through RE2. ----
  c.push_back({"--filter with a back-reference",
               [](const fs::path&) {},
               "run {R}/scenarios/paper.toml --filter '(a)\\1' --out {D}/out",
               2,
               {"--filter", "not a usable regular expression", "RE2"},
               {},
               {"{D}/out"}});

  // ---- Files rabbit wrote and reads back: bounded too, naming the file and the limit. ----
  c.push_back({"manifest.csv: 5 MB (gaits build)",
               [](const fs::path& d) {
                 WriteText(d / "t.toml", "[[gait]]\nv_m = 0.3\n[[gait]]\nv_m = 0.4\n");
                 Sparse(d / "db/manifest.csv", 5000000);
               },
               "gaits build {D}/t.toml -q --out {D}/db",
               2,
               {"{D}/db/manifest.csv", "larger than 4 MiB", "manifest files"},
               {"{D}/t.toml"},
               {"{D}/db/.build"}});
  c.push_back({"walker.csv: 5 MB (a walker on the database)",
               [](const fs::path& d) {
                 Sparse(d / "db/walker.csv", 5000000);
                 WriteText(d / "s.toml",
                           WalkerScenario(kRoot + "/gaits/reference",
                                          "database = \"" + (d / "db").string() + "\"\n"));
               },
               "simulate {D}/s.toml --out {D}/t.csv",
               2,
               {"{D}/db/walker.csv", "larger than 4 MiB", "walker settings files"},
               {"{D}/s.toml"},
               {"{D}/t.csv"}});
  c.push_back({"shard marker: 2 MB (report merging shards)",
               [](const fs::path& d) { Sparse(d / "rep/shards/1-of-1/.rabbit-shard", 2000000); },
               "report {D}/rep",
               2,
               {"{D}/rep/shards/1-of-1/.rabbit-shard", "larger than 1 MiB", "marker files"},
               {"{D}/rep"},
               {"{D}/rep.merging"}});
  c.push_back({"run staging marker: 2 MB (run --resume)",
               [](const fs::path& d) {
                 WriteText(d / "s.toml",
                           "[suite]\nname = \"h\"\n[[scenario]]\nname = \"a\"\n" + kDropInSuite);
                 Sparse(d / "out.partial/.rabbit-staging", 2000000);
               },
               "run {D}/s.toml --jobs 1 --no-html -q --resume --out {D}/out",
               2,
               {"{D}/out.partial/.rabbit-staging", "larger than 1 MiB", "marker files"},
               {"{D}/out.partial"},
               {"{D}/out"}});
  c.push_back({"tuning job marker: 2 MB (tune --resume)",
               [](const fs::path& d) {
                 WriteText(d / "job.toml",
                           "[job]\nsuites = [\"" + kRoot +
                               "/scenarios/tune_ramp.toml\"]\nfilter = "
                               "\"^ramp_up$\"\nmax_evaluations = 2\nalgorithm = \"sbplx\"\n"
                               "[objective]\nspeed_error = 1.0\n[[parameter]]\n"
                               "path = \"controller.k_p\"\nlower = 0.0\n"
                               "upper = 0.6\n");
                 Sparse(d / "job/.rabbit-tune", 2000000);
                 WriteText(d / "job/evaluations.csv", "eval\n");
               },
               "tune {D}/job.toml -q --no-html --resume --out {D}/job",
               2,
               {"{D}/job/.rabbit-tune", "larger than 1 MiB", "marker files"},
               {"{D}/job"},
               {"{D}/job/best.toml"}});
  return c;
}

class HostileInputTest : public ::testing::TestWithParam<size_t> {
 protected:
  static void SetUpTestSuite() { std::signal(SIGPIPE, SIG_IGN); }
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_hostile_" + std::to_string(::getpid()) + "_" + std::to_string(GetParam()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_P(HostileInputTest, RefusedNamingThePlaceAndLeavingEverythingAsItWas) {
  const Case c = Cases()[GetParam()];
  SCOPED_TRACE(c.name);
  c.setup(dir_);
  std::map<std::string, std::string> before;
  for (const std::string& p : c.untouched) before.merge(Snapshot(Expand(p, dir_)));
  ASSERT_TRUE(c.untouched.empty() || !before.empty());
  const std::map<std::string, std::string> shipped = Snapshot(kRoot + "/gaits");
  CliRun run;
  {
    std::unique_ptr<FifoWriter> writer;
    if (!c.fifo.empty()) writer = std::make_unique<FifoWriter>(dir_ / c.fifo, c.fifo_bytes);
    run = RunCli(Expand(c.args, dir_));
  }
  EXPECT_EQ(run.code, c.code) << run.output;
  for (const std::string& f : c.fragments) {
    EXPECT_NE(run.output.find(Expand(f, dir_)), std::string::npos)
        << "missing \"" << Expand(f, dir_) << "\" in: " << run.output.substr(0, 2000);
  }
  EXPECT_LT(run.output.size(), 4000u) << "an error is one short message";
  std::map<std::string, std::string> after;
  for (const std::string& p : c.untouched) after.merge(Snapshot(Expand(p, dir_)));
  EXPECT_TRUE(before == after) << "an input was changed";
  for (const std::string& p : c.absent) EXPECT_FALSE(fs::exists(Expand(p, dir_))) << p;
  EXPECT_TRUE(Snapshot(kRoot + "/gaits") == shipped) << "the shipped gaits changed";
}

INSTANTIATE_TEST_SUITE_P(Table, HostileInputTest, ::testing::Range<size_t>(0, Cases().size()),
                         [](const ::testing::TestParamInfo<size_t>& row) {
                           std::string name = std::to_string(row.param) + "_";
                           const std::string text = Cases()[row.param].name;
                           for (char ch : text) {
                             name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                           }
                           return name;
                         });

}  // namespace
