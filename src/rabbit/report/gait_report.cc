#include "rabbit/report/gait_report.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "rabbit/gait/gait_database.h"
#include "rabbit/io/atomic_file.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/io/test_hooks.h"
#include "rabbit/report/svg.h"

namespace rabbit {

std::string WriteGaitReport(const std::string& dir, const std::string& out_dir) {
  namespace fs = std::filesystem;
  // Only a gait report rabbit wrote is replaced; written whole in a staging folder beside it.
  fs::path out = fs::path(out_dir).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();  // "dir/" -> "dir"
  const fs::path staging = out.string() + ".partial";
  const OutputLock lock =
      ClaimMarkedFolder("--out", out, staging, kGaitReportMarker, "a gait report of rabbit");
  const std::vector<GaitIndexEntry> index = ReadGaitIndex((fs::path(dir) / "index.csv").string());
  // Every gait file is read before the first walk: a bad one is named before the work.
  std::vector<GaitRecord> gaits;
  for (const GaitIndexEntry& entry : index) {
    gaits.push_back(ReadGaitFile((fs::path(dir) / entry.file).string()));
  }
  TestKillPoint("gaits-report-walking");
  const Model model{ModelParams{}};
  SimSetup setup;
  setup.model = &model;
  constexpr double kDeg = 180.0 / M_PI;
  std::ostringstream html, sections;
  std::vector<PlotSeries> all_hip, all_knee;
  html << "<!DOCTYPE html><html><head><meta charset='utf-8'><title>rabbit-gait: reference "
          "gaits</title><style>body{font-family:sans-serif;margin:2em;max-width:1400px}"
          "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px 8px;"
          "text-align:right}svg{display:block;margin:1em 0}</style></head><body>";
  html << "<h1>Reference gaits</h1><p>Database <code>" << HtmlEscape(dir)
       << "</code>; each gait re-walked from its documented start with the stored pragmatic-rule "
          "parameters. Figures over the last 10 steps of 20 s of walking.</p>";
  html << "<table><tr><th>gait</th><th>target V<sub>M</sub> m/s</th><th>V<sub>M</sub> m/s</th>"
          "<th>L<sub>step</sub> m</th><th>L<sub>step</sub> spread m</th><th>t<sub>step</sub> s"
          "</th><th>steps</th><th>saturation s</th><th>q<sub>r1</sub><sup>dsw</sup> deg</th>"
          "<th>q<sub>i2</sub><sup>dsw</sup> deg</th><th>q<sub>0</sub><sup>d</sup> deg</th></tr>";
  for (const GaitRecord& gait : gaits) {
    const GaitRun run = WalkGait(setup, gait.spec, 20.0, 10);
    const GaitMetrics& m = run.metrics;
    char row[400];
    std::snprintf(row, sizeof row,
                  "<td>%.2f</td><td>%.3f</td><td>%.3f</td><td>%.4f</td>"
                  "<td>%.3f</td><td>%d</td><td>%.2f</td><td>%.1f</td><td>%.1f</td><td>%.1f</td>"
                  "</tr>",
                  gait.target_v_m, m.v_m, m.l_step, m.l_step_spread, m.t_step, m.steps,
                  m.saturation_time, gait.spec.rules.qr1_dsw * kDeg, gait.spec.rules.qi2_dsw * kDeg,
                  gait.spec.rules.q0_d * kDeg);
    html << "<tr><td>" << HtmlEscape(gait.name) << "</td>" << row;
    // Figure 8: 2.8 s of steady walking (the last 2.8 s of the run), a figure every 0.1 s.
    const double t1 = run.sim.t_end, t0 = t1 - 2.8;
    sections << "<h2>" << HtmlEscape(gait.name) << "</h2>"
             << StickDiagramSvg(model, run.sim.samples, Terrain{}, t0, t1, 0.1);
    PlotSeries q1{"hip q_i1", {}, {}}, q2{"knee q_i2", {}, {}}, w1{"hip rate", {}, {}},
        w2{"knee rate", {}, {}};
    for (const SwingSample& s : gait.swing) {
      q1.x.push_back(s.e * kDeg);
      q1.y.push_back(s.q1 * kDeg);
      q2.x.push_back(s.e * kDeg);
      q2.y.push_back(s.q2 * kDeg);
      w1.x.push_back(s.e * kDeg);
      w1.y.push_back(s.qd1 * kDeg);
      w2.x.push_back(s.e * kDeg);
      w2.y.push_back(s.qd2 * kDeg);
    }
    sections << LinePlotSvg(gait.name + ": swing-leg angles", "e = stance hip angle (deg)",
                            "angle (deg)", {q1, q2})
             << LinePlotSvg(gait.name + ": swing-leg rates", "e = stance hip angle (deg)",
                            "rate (deg/s)", {w1, w2});
    all_hip.push_back({gait.name, q1.x, q1.y});
    all_knee.push_back({gait.name, q2.x, q2.y});
  }
  html << "</table>";
  html << "<h2>All gaits</h2>"
       << LinePlotSvg("swing hip q_i1 against e", "e (deg)", "q_i1 (deg)", all_hip)
       << LinePlotSvg("swing knee q_i2 against e", "e (deg)", "q_i2 (deg)", all_knee);
  html << sections.str() << "</body></html>\n";
  const std::string page = html.str();
  WriteMarkedFolder(staging, out, kGaitReportMarker, "gaits-report", [&] {
    WriteFileAtomically((staging / "index.html").string(), [&page](std::ostream& o) { o << page; });
  });
  return (out / "index.html").string();
}

}  // namespace rabbit
