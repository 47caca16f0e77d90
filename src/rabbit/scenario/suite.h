// Scenario suites (docs/formats/suite.md): one TOML file holding many scenarios.
//
//   [suite]                  name (default: the file's stem), description
//   [suite.targets]          group = success rate in (0, 1] (a family's or a scenario's name)
//   [defaults]               any scenario keys, under every scenario and family template
//   [[scenario]]             a scenario, exactly as in a scenario file (its keys over [defaults])
//   [[family]]               a randomised family, expanded deterministically into `count` scenarios
//     name, count, seed
//     [family.scenario]      the template (over [defaults])
//     [family.draw]          name = [low, high] (or a table, or "=expression"): a named draw that
//                            several keys can share
//     [family.vary]          "dotted.key.path" = [low, high] or "=expression" (over the draws):
//                            drawn per member; array elements by 1-based index, e.g.
//                            "terrain.obstacles.1.x_start"; "velocity.changes" = { count, every_s,
//                            v, ... } generates the velocity profile (family_draws.h)
//   Member i (0-based) is named <family name>-<i, 3 digits>, gets seed = a hash of (family seed, i)
//   unless the template sets one, and draws its values from a hash of (seed, i, key name):
//   the same members whatever the machine, the thread count or the other families.
//
// Relative paths in a suite resolve against the suite file's directory.
#ifndef RABBIT_SCENARIO_SUITE_H_
#define RABBIT_SCENARIO_SUITE_H_

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/scenario/scenario.h"

namespace rabbit {

// One member of a family and the values it drew (key path or draw name, value), in draw order.
struct MemberRow {
  std::string name;
  std::uint64_t seed = 0;
  std::vector<std::pair<std::string, double>> values;
};
struct FamilyMembers {
  std::string family;
  std::vector<MemberRow> members;
};

struct Suite {
  std::string file, name, description;
  std::vector<Scenario> scenarios;  // file order, families expanded in place
  // [suite.targets] group = rate: the success rate the main variant should reach on a family (or
  // a plain scenario), in (0, 1]; reported (comparison.csv, the page) with the gap, never failing
  // the run. In file order.
  std::vector<std::pair<std::string, double>> targets;
  // Every family's members with their draws, in file order (members.csv).
  std::vector<FamilyMembers> members;
};

// The name of the report file listing every family member's draws.
constexpr const char* kMembersFile = "members.csv";
// Its text: family,scenario,seed and one column per drawn key or draw name (over all families,
// in order of first appearance; empty where a family does not draw it). Empty when the suite has
// no family.
std::string MembersCsv(const Suite& suite);

// The text of a report's targets.csv (group,target_success_rate; see kTargetsFile in
// rabbit/report/comparison.h), written by `rabbit run` when the suite has targets.
std::string TargetsCsv(const Suite& suite);

// Checks a suite file that `key` on `line` of `file` names, to be run later (a tuning job's suites
// and guards; a gait build's check suite, which runs on the database once it is built), as far as
// can be done without its gait database: a readable TOML file that is a suite or a scenario, not
// another kind of rabbit file. Throws InputError otherwise, given at that place and followed by
// the suite file's own error.
void CheckNamedSuiteFile(const std::string& path, const std::string& file, int line,
                         const std::string& key);

// Reads, expands and validates a suite; scenario names must be unique. A single scenario file is
// read as a suite of one, named after the scenario. Throws InputError naming
// the file, line and key (for a family member: the family's keys, and the member's name).
// With an overlay, its parameters replace the settings of every scenario (see params.h).
// With `settings`, records each scenario's effective numeric settings (see ReadScenario).
Suite LoadSuite(const std::string& path, const ParamOverlay* overlay = nullptr,
                std::vector<std::map<std::string, double>>* settings = nullptr);

// The value a family member draws for one varied key, in [low, high): a hash of the family's seed,
// the member's index and the key's name (adding or removing another key changes nothing).
double FamilyDraw(std::uint64_t family_seed, int member, const std::string& key, double low,
                  double high);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_SUITE_H_
