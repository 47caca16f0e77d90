#include "tune_log.h"

#include <csignal>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/ranks.h"

namespace rabbit::tune_internal {

namespace fs = std::filesystem;

std::string CsvText(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"')
      out += "\"\"";
    else if (c == '\n' || c == '\r')
      out += ' ';
    else
      out += c;
  }
  return out + "\"";
}

std::string EvaluationsHeader(const TuneJob& job) {
  std::string h = "eval,round,start,seq,objective";
  for (int t = 0; t < kNumTuneTerms; ++t) h += std::string(",") + TuneTermName(t);
  h += ",runs,failed";
  for (const TuneParameter& p : job.parameters) h += "," + p.name;
  return h + ",guards_run,guard_broken,error,wall_s";
}

std::string RunsHeader() {
  std::string h = "eval,suite,scenario,passed,outcome";
  for (int t = 0; t < kNumTuneTerms; ++t) h += std::string(",") + TuneTermName(t);
  return h;
}

std::string EvaluationRow(const Evaluation& e) {
  std::string row = std::to_string(e.index) + "," + std::to_string(e.round) + "," +
                    std::to_string(e.start) + "," + std::to_string(e.seq) + "," +
                    ExactNumber(e.objective);
  for (double v : e.terms) row += "," + ExactNumber(v);
  row += "," + std::to_string(e.runs) + "," + std::to_string(e.failed);
  for (double v : e.x) row += "," + ExactNumber(v);
  char wall[32];
  std::snprintf(wall, sizeof wall, "%.3f", e.wall);
  return row + "," + (e.guards_run ? "1" : "0") + "," + CsvText(e.guard_broken) + "," +
         CsvText(e.error) + "," + wall;
}

std::string RunRows(const Evaluation& e) {
  std::string rows;
  for (const RunScore& s : e.scores) {
    rows += std::to_string(e.index) + "," + s.suite + "," + s.scenario + "," +
            (s.passed ? "1" : "0") + "," + s.outcome;
    for (double v : s.value) rows += "," + ExactNumber(v);
    rows += "\n";
  }
  return rows;
}

std::string CompleteLines(const std::string& text) {
  const size_t end = text.rfind('\n');
  return end == std::string::npos ? "" : text.substr(0, end + 1);
}

std::string ReadText(const fs::path& path, const FileLimits& limits) {
  return ReadBoundedFileIfExists(path.string(), limits);
}

std::map<std::pair<int, int>, Evaluation> ParseLog(const TuneJob& job, const std::string& file,
                                                   const std::string& evaluations,
                                                   const std::string& runs) {
  std::map<std::pair<int, int>, Evaluation> out;
  if (evaluations.empty()) return out;
  const CsvTable table = CsvTable::Parse(evaluations, file);
  const std::string expected = EvaluationsHeader(job);
  std::string header;
  for (const std::string& h : table.header()) header += (header.empty() ? "" : ",") + h;
  if (header != expected) {
    throw InputError(file, 1, "", "the log's columns are not this job's (" + header + ")");
  }
  std::map<int, Evaluation*> by_index;
  for (size_t r = 0; r < table.num_rows(); ++r) {
    Evaluation e;
    size_t c = 0;
    e.index = table.Integer(r, c++);
    e.round = table.Integer(r, c++);
    e.start = table.Integer(r, c++);
    e.seq = table.Integer(r, c++);
    e.objective = table.Number(r, c++, CsvNumber::kAny);
    for (double& v : e.terms) v = table.Number(r, c++, CsvNumber::kAny);
    e.runs = table.Integer(r, c++);
    e.failed = table.Integer(r, c++);
    for (size_t p = 0; p < job.parameters.size(); ++p) e.x.push_back(table.Number(r, c++));
    e.guards_run = table.Integer(r, c++) != 0;
    e.guard_broken = table.Text(r, c++);
    e.error = table.Text(r, c++);
    e.wall = table.Number(r, c++, CsvNumber::kAny);
    auto [it, inserted] = out.emplace(std::make_pair(e.start, e.seq), std::move(e));
    if (!inserted) {
      throw InputError(file, table.line(r), "",
                       "search " + std::to_string(it->first.first) + " request " +
                           std::to_string(it->first.second) + " is logged twice");
    }
    by_index[it->second.index] = &it->second;
  }
  if (!runs.empty()) {
    const CsvTable rt = CsvTable::Parse(runs, file);
    for (size_t r = 0; r < rt.num_rows(); ++r) {
      const auto found = by_index.find(rt.Integer(r, 0));
      if (found == by_index.end()) continue;  // an evaluation the crash cut short
      RunScore s;
      s.suite = rt.Text(r, 1);
      s.scenario = rt.Text(r, 2);
      s.passed = rt.Integer(r, 3) != 0;
      s.outcome = rt.Text(r, 4);
      for (int t = 0; t < kNumTuneTerms; ++t) s.value[t] = rt.Number(r, 5 + t, CsvNumber::kAny);
      found->second->scores.push_back(std::move(s));
    }
  }
  for (auto& [key, e] : out) {
    if (static_cast<int>(e.scores.size()) != e.runs) {
      throw InputError(file, 0, "",
                       "evaluation " + std::to_string(e.index) + " logs " + std::to_string(e.runs) +
                           " runs but runs.csv holds " + std::to_string(e.scores.size()));
    }
  }
  return out;
}

Log::~Log() {
  if (evaluations_ != nullptr) std::fclose(evaluations_);
  if (runs_ != nullptr) std::fclose(runs_);
}

void Log::Open(const fs::path& dir, const TuneJob& job, const std::string& evaluations,
               const std::string& runs) {
  if (!Ranks::root()) return;
  // Rewrite what survived (complete lines only), then append.
  const fs::path e = dir / "evaluations.csv", r = dir / "runs.csv";
  WriteFileAtomically(e.string(), [&](std::ostream& out) {
    out << (evaluations.empty() ? EvaluationsHeader(job) + "\n" : evaluations);
  });
  WriteFileAtomically(
      r.string(), [&](std::ostream& out) { out << (runs.empty() ? RunsHeader() + "\n" : runs); });
  evaluations_ = std::fopen(e.string().c_str(), "ab");
  runs_ = std::fopen(r.string().c_str(), "ab");
  if (evaluations_ == nullptr || runs_ == nullptr) {
    throw std::runtime_error("cannot append to the log in " + dir.string());
  }
}

void Log::Append(const Evaluation& e) {
  if (evaluations_ == nullptr) return;
  const std::string runs = RunRows(e), row = EvaluationRow(e) + "\n";
  if (std::fputs(runs.c_str(), runs_) < 0 || std::fflush(runs_) != 0 ||
      std::fputs(row.c_str(), evaluations_) < 0 || std::fflush(evaluations_) != 0) {
    throw std::runtime_error("cannot append to the log (disk full?)");
  }
  // For the resume tests: RABBIT_TUNE_KILL_AFTER=N kills the process (SIGKILL, no clean-up)
  // once N evaluations have been logged, half-way through writing the next row's text.
  if (kill_after_ > 0 && ++appended_ == kill_after_) {
    std::fputs("999,0,0", evaluations_);
    std::fflush(evaluations_);
    std::raise(SIGKILL);
  }
}

}  // namespace rabbit::tune_internal
