// The grammar of the rabbit command line, checked on the app itself (cli/app.h): every option's
// default is shown in --help, a flag name means the same on every command, every command that
// prints progress takes -q and every one that runs in parallel -j, -o/--out says which kind of
// output it writes, the help names only options that exist, and a command's summary lists its
// subcommands.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "cli/app.h"

namespace {

struct Leaf {
  std::string path;  // "gaits synthesize"
  const CLI::App* app;
  std::vector<const CLI::App*> ancestors;  // the root first
};

void Walk(const CLI::App* app, const std::string& path, std::vector<const CLI::App*> ancestors,
          std::vector<Leaf>* leaves, std::vector<Leaf>* parents) {
  const std::vector<const CLI::App*> subs =
      app->get_subcommands([](const CLI::App*) { return true; });
  if (subs.empty()) {
    leaves->push_back({path, app, ancestors});
    return;
  }
  if (!path.empty()) parents->push_back({path, app, ancestors});
  ancestors.push_back(app);
  for (const CLI::App* sub : subs) {
    Walk(sub, path.empty() ? sub->get_name() : path + " " + sub->get_name(), ancestors, leaves,
         parents);
  }
}

bool Visible(const CLI::Option* o) { return !o->get_group().empty(); }
bool IsHelp(const CLI::Option* o) { return o->get_name() == "--help" || o->get_name() == "-h"; }
bool IsFlag(const CLI::Option* o) { return o->get_expected_max() == 0; }

// Every visible option of a command, --help left out.
std::vector<const CLI::Option*> Options(const CLI::App* app) {
  std::vector<const CLI::Option*> out;
  for (const CLI::Option* o : app->get_options()) {
    if (Visible(o) && !IsHelp(o)) out.push_back(o);
  }
  return out;
}

const CLI::Option* Find(const CLI::App* app, const std::string& long_name) {
  for (const CLI::Option* o : app->get_options()) {
    for (const std::string& n : o->get_lnames()) {
      if ("--" + n == long_name) return o;
    }
  }
  return nullptr;
}

class CliGrammarTest : public ::testing::Test {
 protected:
  void SetUp() override {
    rabbit::cli::BuildApp(&app_);
    Walk(&app_, "", {}, &leaves_, &parents_);
  }
  const Leaf& LeafNamed(const std::string& path) const {
    for (const Leaf& l : leaves_) {
      if (l.path == path) return l;
    }
    ADD_FAILURE() << "no command " << path;
    return leaves_.front();
  }
  CLI::App app_{"rabbit-gait", "rabbit"};
  std::vector<Leaf> leaves_, parents_;
};

TEST_F(CliGrammarTest, FindsEveryCommand) {
  std::set<std::string> paths;
  for (const Leaf& l : leaves_) paths.insert(l.path);
  for (const char* expected :
       {"simulate", "gaits synthesize", "gaits generate", "gaits report", "gaits list", "train",
        "fis eval", "fis generate", "run", "report", "tune"}) {
    EXPECT_EQ(paths.count(expected), 1u) << expected;
  }
}

// An option's default is either captured (and then printed by --help as TYPE=default) or, when
// it is empty (a default that depends on something else, or none), described in words.
TEST_F(CliGrammarTest, EveryDefaultIsShownInHelp) {
  for (const Leaf& l : leaves_) {
    const std::string help = l.app->help();
    for (const CLI::Option* o : Options(l.app)) {
      if (IsFlag(o) || o->get_required()) continue;
      const std::string name = l.path + " " + o->get_name();
      if (o->get_default_str().empty()) {
        EXPECT_NE(o->get_description().find("default"), std::string::npos)
            << name << ": no default shown, and the help does not say what it is";
      } else {
        EXPECT_NE(help.find("=" + o->get_default_str()), std::string::npos)
            << name << ": the default " << o->get_default_str() << " is not in its --help";
      }
    }
  }
}

// A long name has one short name wherever it appears, and a short name one long name; the
// common ones have their short name everywhere.
TEST_F(CliGrammarTest, SameFlagNamesOnEveryCommand) {
  const std::map<std::string, std::string> common = {
      {"out", "o"}, {"jobs", "j"}, {"quiet", "q"}, {"verbose", "v"}};
  std::map<std::string, std::set<std::string>> short_of, long_of;
  for (const Leaf& l : leaves_) {
    for (const CLI::Option* o : Options(l.app)) {
      const std::vector<std::string>& longs = o->get_lnames();
      const std::vector<std::string>& shorts = o->get_snames();
      for (const std::string& n : longs) {
        short_of[n].insert(shorts.empty() ? "" : shorts.front());
        const auto it = common.find(n);
        if (it != common.end()) {
          EXPECT_EQ(shorts, std::vector<std::string>{it->second})
              << l.path << " --" << n << " needs -" << it->second;
        }
      }
      for (const std::string& s : shorts) long_of[s].insert(longs.empty() ? "" : longs.front());
    }
  }
  for (const auto& [name, shorts] : short_of) {
    EXPECT_EQ(shorts.size(), 1u) << "--" << name << " has different short names";
  }
  for (const auto& [name, longs] : long_of) {
    EXPECT_EQ(longs.size(), 1u) << "-" << name << " means different options";
  }
}

// Every command that prints progress or results besides its product takes -q; the listing
// commands (their output is the product) do not need it.
TEST_F(CliGrammarTest, QuietAndJobsWhereTheyApply) {
  const std::set<std::string> product_is_output = {"gaits list", "fis eval"};
  for (const Leaf& l : leaves_) {
    if (product_is_output.count(l.path) != 0) continue;
    EXPECT_NE(Find(l.app, "--quiet"), nullptr) << l.path << " has no -q/--quiet";
  }
  for (const char* parallel : {"run", "tune", "gaits generate"}) {
    EXPECT_NE(Find(LeafNamed(parallel).app, "--jobs"), nullptr) << parallel << " has no -j";
  }
}

// -o/--out is always where the command writes, and its help says whether a file or a folder.
TEST_F(CliGrammarTest, OutSaysWhichKindOfOutput) {
  int outs = 0;
  for (const Leaf& l : leaves_) {
    const CLI::Option* out = Find(l.app, "--out");
    if (out == nullptr) continue;
    ++outs;
    const std::string& d = out->get_description();
    EXPECT_TRUE(std::regex_search(d, std::regex("^[A-Za-z ]*(file|folder)")))
        << l.path << ": " << d;
  }
  EXPECT_GE(outs, 6);
}

// The gait database is one flag name on every command that reads or writes it. Today gaits
// names it --dir and train and fis generate --gaits; once gaits names it --gaits too, --dir may
// only be a hidden alias.
TEST_F(CliGrammarTest, OneFlagForTheGaitDatabase) {
  std::set<std::string> names;
  for (const Leaf& l : leaves_) {
    for (const CLI::Option* o : Options(l.app)) {
      if (o->get_description().rfind("Gait database", 0) == 0) names.insert(o->get_name());
    }
  }
  if (Find(LeafNamed("gaits list").app, "--gaits") != nullptr) {
    EXPECT_EQ(names, std::set<std::string>{"--gaits"});
    for (const Leaf& l : leaves_) {
      const CLI::Option* dir = Find(l.app, "--dir");
      EXPECT_TRUE(dir == nullptr || !Visible(dir)) << l.path << " shows --dir";
    }
  } else {
    EXPECT_EQ(names, (std::set<std::string>{"--dir", "--gaits"}));
  }
}

// Every --flag a help text names is an option of that command (or of rabbit itself).
TEST_F(CliGrammarTest, HelpNamesOnlyRealOptions) {
  const std::regex flag("--[a-z][a-z0-9-]*");
  for (const Leaf& l : leaves_) {
    std::vector<std::string> texts = {l.app->get_description()};
    for (const CLI::Option* o : Options(l.app)) texts.push_back(o->get_description());
    for (const std::string& text : texts) {
      for (std::sregex_iterator it(text.begin(), text.end(), flag), end; it != end; ++it) {
        const std::string name = it->str();
        bool known = Find(l.app, name) != nullptr;
        for (const CLI::App* a : l.ancestors) known = known || Find(a, name) != nullptr;
        EXPECT_TRUE(known) << l.path << ": the help names " << name << ", which it has not";
      }
    }
  }
}

// A command with subcommands lists them all in its summary line.
TEST_F(CliGrammarTest, SummariesListTheirSubcommands) {
  ASSERT_FALSE(parents_.empty());
  for (const Leaf& p : parents_) {
    for (const CLI::App* sub : p.app->get_subcommands([](const CLI::App*) { return true; })) {
      EXPECT_NE(p.app->get_description().find(sub->get_name()), std::string::npos)
          << p.path << ": its summary omits " << sub->get_name();
    }
  }
}

// The data root is one option of rabbit itself, taken by every command.
TEST_F(CliGrammarTest, DataRootOption) {
  const CLI::Option* data = Find(&app_, "--data");
  ASSERT_NE(data, nullptr);
  EXPECT_NE(data->get_description().find("RABBIT_DATA"), std::string::npos);
  EXPECT_NE(rabbit::cli::VersionText().find("data root"), std::string::npos);
}

}  // namespace
