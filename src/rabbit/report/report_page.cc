// The HTML pieces of the report page (report_page.h).
#include "rabbit/report/report_page.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "rabbit/report/svg.h"

namespace rabbit {
namespace report_internal {
namespace {

// A number for the replay's JSON: fixed decimals, trailing zeros dropped.
std::string JsonNumber(double v, int decimals) {
  if (!std::isfinite(v)) return "null";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  std::string s = buffer;
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

// A table cell's number: "-" for missing, infinity spelled out.
std::string CellNumber(double v, int decimals) {
  if (std::isnan(v)) return "&ndash;";
  if (std::isinf(v)) return v > 0 ? "&infin;" : "&minus;&infin;";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

}  // namespace

const char kStyle[] = R"css(
:root{--fg:#1d1f23;--muted:#5f6670;--line:#d5d9de;--pass:#e2f3e5;--fail:#fbe2df}
*{box-sizing:border-box}
body{font:15px/1.5 "DejaVu Sans",system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;color:var(--fg);margin:0;background:#eef0f3}
main{max-width:1360px;margin:0 auto;padding:28px 30px 64px;background:#fff;min-height:100vh}
h1{font-size:27px;margin:0 0 4px;font-weight:650}
h2{font-size:21px;margin:44px 0 6px;padding-top:14px;border-top:2px solid #e3e6ea}
h3{font-size:16px;margin:26px 0 6px;color:#2c3440}
p{margin:6px 0}
.note{color:var(--muted);font-size:13.5px}
.warning{background:#fff4d6;border:1px solid #f0d48a;padding:8px 12px;border-radius:4px;font-size:14px}
table{border-collapse:collapse;font-size:12.5px}
th,td{border:1px solid var(--line);padding:4px 6px;text-align:right;vertical-align:top}
th{background:#f1f3f6;font-weight:600;text-align:center}
td.text{text-align:left}
td.scenario{text-align:left;font-weight:600;background:#fafbfc}
td{white-space:nowrap}
td.criteria{text-align:left;white-space:normal;font-size:12.5px;color:#8a1c14;background:#fdf3f2;border-top:0}
td.criteria ul{display:inline;margin:0;padding:0}
td.criteria li{display:inline;margin-left:10px}
td.criteria li+li:before{content:"\2022\00a0";color:#c0a0a0}
td.variant{text-align:left;white-space:nowrap}
td.variant.baseline{font-style:italic;color:#4a5058}
td.status{white-space:nowrap}
.reason{font-size:11.5px;color:var(--muted);white-space:normal;min-width:110px;max-width:150px}
table.summary{font-size:12px}
table.summary td,table.summary th{padding:3px 3px}
table.summary th{font-size:11.5px}
tr.pass td.status{background:var(--pass);color:#16652a;font-weight:700}
tr.fail td.status{background:var(--fail);color:#a3150f;font-weight:700}
tr.group-start td{border-top:2px solid #9aa3ad}
.swatch{display:inline-block;width:11px;height:11px;border-radius:2px;margin-right:6px;vertical-align:-1px}
.table-wrap{overflow-x:auto}
figure{margin:10px 0 22px}
figure img{display:block;max-width:100%;height:auto;border:1px solid #e6e8eb;border-radius:3px}
figcaption{font-size:13px;color:var(--muted);max-width:1000px;margin-top:4px}
details{margin:10px 0}
summary{cursor:pointer;color:#2c3440;font-weight:600}
.replay{margin:8px 0 24px;max-width:1000px}
.replay h4{margin:0 0 4px;font-size:14.5px}
.replay canvas{display:block;width:100%;height:auto;border:1px solid #d9dde2;border-radius:4px;background:#fff}
.controls{display:flex;gap:10px;align-items:center;margin-top:6px;font-size:13.5px}
.controls button{min-width:82px;padding:3px 10px;font:inherit;cursor:pointer}
.controls input[type=range]{flex:1}
.controls .time{font-variant-numeric:tabular-nums;min-width:150px;text-align:right;color:var(--muted)}
code{background:#f3f4f6;padding:0 3px;border-radius:3px}
.muted{color:var(--muted)}
table.comparison td.rate{font-variant-numeric:tabular-nums}
.group{margin:18px 0 8px}
.verdict{font-size:16px;padding:8px 12px;border-radius:4px;margin:12px 0 4px}
.verdict.pass{background:var(--pass)}
.verdict.fail{background:var(--fail)}
details.run-detail>summary{font-size:15px;margin:6px 0}
th{white-space:normal}
)css";

const char kErrorCounter[] =
    "document.documentElement.dataset.jsErrors='0';"
    "function rabbitCountError(){var d=document.documentElement.dataset;"
    "d.jsErrors=String((parseInt(d.jsErrors,10)||0)+1);}"
    "window.addEventListener('error',rabbitCountError);"
    "window.addEventListener('unhandledrejection',rabbitCountError);";

// The replays: each .replay element holds a canvas, controls and its frames as JSON
// {fps, t: [...], p: [12 numbers per frame: hip, trunk top, knee 1, foot 1, knee 2, foot 2],
//  c: [contact bits per frame], obs: [[x_start, length, height, base], ...],
//  g: the ground profile [x_k, height_k, grade_k (dy/dx from x_k on), ...], flat before x_0
//  (empty: flat y = 0)}.
const char kReplayScript[] = R"js(
(function(){
  var root=document.documentElement;
  var LEG=['#0072B2','#D55E00'], TRUNK='#404040';
  function Replay(el){
    var d=JSON.parse(el.querySelector('script.replay-data').textContent);
    var canvas=el.querySelector('canvas'), ctx=canvas.getContext('2d');
    var button=el.querySelector('button.play'), slider=el.querySelector('input.seek');
    var speed=el.querySelector('select.speed'), label=el.querySelector('.time');
    var n=d.t.length, frame=Math.max(0,Math.min(n-1,d.start||0)), playing=false, last=0, clock=0;
    var W=canvas.width, H=canvas.height, ratio=window.devicePixelRatio||1;
    canvas.width=Math.round(W*ratio); canvas.height=Math.round(H*ratio);
    slider.max=String(Math.max(0,n-1));
    var yLo=-0.14, yHi=1.76, s=H/(yHi-yLo);
    // Ground height at x (the profile d.g; flat before its first point).
    function G(x){var g=d.g||[]; if(!g.length||x<g[0]) return g.length?g[1]:0; var h=g[1];
      for(var i=0;i<g.length&&x>=g[i];i+=3) h=g[i+1]+g[i+2]*(x-g[i]); return h;}
    function draw(){
      ctx.setTransform(ratio,0,0,ratio,0,0);
      ctx.fillStyle='#ffffff'; ctx.fillRect(0,0,W,H);
      if(n===0){ctx.fillStyle='#555';ctx.font='15px sans-serif';ctx.fillText('no trajectory recorded',20,30);return;}
      var p=d.p, o=12*frame, hx=p[o];
      var left=hx-0.42*W/s, right=left+W/s, base=G(hx);
      // The camera follows the hip along x and the ground under it in y.
      function X(x){return (x-left)*s;} function Y(y){return (yHi+base-y)*s;}
      var ground=[left], g=d.g||[];
      for(var i=0;i<g.length;i+=3){if(g[i]>left&&g[i]<right) ground.push(g[i]);}
      ground.push(right);
      ctx.fillStyle='#efe8dc'; ctx.beginPath(); ctx.moveTo(0,H);
      for(var i=0;i<ground.length;i++) ctx.lineTo(X(ground[i]),Y(G(ground[i])));
      ctx.lineTo(W,H); ctx.closePath(); ctx.fill();
      ctx.strokeStyle='#555'; ctx.lineWidth=2; ctx.beginPath();
      for(var i=0;i<ground.length;i++){var gx=X(ground[i]),gy=Y(G(ground[i])); if(i) ctx.lineTo(gx,gy); else ctx.moveTo(gx,gy);}
      ctx.stroke();
      ctx.lineWidth=1; ctx.fillStyle='#6b6256'; ctx.font='11px sans-serif'; ctx.textAlign='center';
      for(var m=Math.ceil(left*4)/4; m<=right; m+=0.25){
        var big=Math.abs(m-Math.round(m))<1e-6, half=Math.abs(2*m-Math.round(2*m))<1e-6, gm=Y(G(m));
        ctx.beginPath(); ctx.moveTo(X(m),gm); ctx.lineTo(X(m),gm+(big?9:half?6:3)); ctx.stroke();
        if(big) ctx.fillText(Math.round(m)+' m',X(m),gm+20);
      }
      for(var k=0;k<d.obs.length;k++){
        var b=d.obs[k], top=(b.length>3?b[3]:0)+b[2];
        if(X(b[0]+b[1])<0||X(b[0])>W) continue;
        ctx.fillStyle='#9a9a9a'; ctx.fillRect(X(b[0]),Y(top),b[1]*s,b[2]*s);
        ctx.strokeStyle='#555'; ctx.strokeRect(X(b[0]),Y(top),b[1]*s,b[2]*s);
      }
      ctx.lineCap='round';
      function seg(i,j,color,width){ctx.strokeStyle=color;ctx.lineWidth=width;ctx.beginPath();
        ctx.moveTo(X(p[o+i]),Y(p[o+i+1]));ctx.lineTo(X(p[o+j]),Y(p[o+j+1]));ctx.stroke();}
      function dot(i,r,fill,color){ctx.beginPath();ctx.arc(X(p[o+i]),Y(p[o+i+1]),r,0,2*Math.PI);
        ctx.fillStyle=fill;ctx.fill();ctx.strokeStyle=color;ctx.lineWidth=1.5;ctx.stroke();}
      var contact=d.c.length?d.c[frame]:0;
      for(var leg=1;leg>=0;leg--){
        var kn=4+4*leg, ft=6+4*leg;
        seg(0,kn,LEG[leg],6); seg(kn,ft,LEG[leg],5);
        dot(kn,3.5,'#fff',LEG[leg]);
        dot(ft,4.5,(contact>>leg)&1?LEG[leg]:'#fff',LEG[leg]);
      }
      seg(0,2,TRUNK,8); dot(0,4.5,'#fff',TRUNK);
      ctx.textAlign='left'; ctx.fillStyle='#333'; ctx.font='13px sans-serif';
      var text='t = '+d.t[frame].toFixed(2)+' s    x = '+hx.toFixed(2)+' m';
      ctx.fillText(text,10,20);
      ctx.fillStyle='#777'; ctx.font='11px sans-serif';
      ctx.fillText('filled foot: on the ground',10,36);
      var st=-1; for(var j=0;4*j<d.s.length&&d.s[4*j]<=d.t[frame]+1e-9;j++) st=j;
      if(st>=0){
        var v=function(x,k){return x===null?'\u2013':x.toFixed(k);};
        ctx.textAlign='right'; ctx.fillStyle='#333'; ctx.font='13px sans-serif';
        ctx.fillText('step '+(st+1)+' of '+(d.s.length/4)+':  V_d '+v(d.s[4*st+1],2)+'  V_M '+
          v(d.s[4*st+2],3)+' m/s  L_step '+v(d.s[4*st+3],3)+' m',W-10,20);
      }
      label.textContent='t = '+d.t[frame].toFixed(2)+' / '+d.t[n-1].toFixed(2)+' s';
      slider.value=String(frame);
    }
    function setButton(){button.textContent=playing?'\u275a\u275a Pause':'\u25b6 Play';}
    function tick(now){
      if(!playing) return;
      // The frame's timestamp may precede the click's performance.now(): never step back.
      clock+=Math.max(0,now-last)/1000*(parseFloat(speed.value)||1); last=Math.max(last,now);
      var f=Math.max(0,Math.min(n-1,Math.floor(clock*d.fps+1e-9)));
      if(f>=n-1){playing=false;setButton();}
      if(f!==frame){frame=f;draw();}
      if(playing) requestAnimationFrame(tick);
    }
    button.addEventListener('click',function(){
      if(playing){playing=false;}else{
        if(frame>=n-1) frame=0;
        clock=frame/d.fps; last=performance.now(); playing=n>1;
        if(playing) requestAnimationFrame(tick);
      }
      setButton();
    });
    slider.addEventListener('input',function(){frame=parseInt(slider.value,10)||0;clock=frame/d.fps;draw();});
    setButton(); draw();
  }
  var all=document.querySelectorAll('.replay'), drawn=0;
  for(var i=0;i<all.length;i++){
    try{Replay(all[i]);drawn++;}catch(e){rabbitCountError();if(window.console)console.error(e);}
  }
  // A link to a scenario opens its collapsed detail.
  function openTarget(){var id=location.hash.slice(1); var el=id&&document.getElementById(id);
    var d=el&&el.querySelector('details'); if(d) d.open=true;}
  window.addEventListener('hashchange',openTarget); openTarget();
  root.dataset.replayCount=String(drawn);
  root.dataset.replay=drawn===all.length?'ready':'failed';
})();
)js";

namespace {

std::string ReplayJson(const RunData& run, const SuiteReportOptions& options) {
  const Trajectory& tr = run.trajectory;
  const int dec = options.replay_decimals;
  std::string t, p, c;
  size_t hint = 0;
  int frames = 0;
  // The frame the replay opens on: near the first event, a second of walking before the hip
  // reaches the first obstacle, else 3 s before the end of a run that did not complete, else 0.
  int start = -1;
  const double event_x = run.terrain.obstacles.empty()
                             ? std::numeric_limits<double>::infinity()
                             : run.terrain.obstacles.front().x_start - 0.6;
  double fps = options.replay_fps;
  if (!tr.t.empty()) {
    const double t0 = tr.t.front(), span = tr.t.back() - t0;
    // At most options.max_replay_frames frames: a longer run is replayed at a lower frame rate
    // (the trajectory reader has checked that the times are finite).
    if (span * fps + 1.0 > options.max_replay_frames) fps = (options.max_replay_frames - 1) / span;
    const int count = static_cast<int>(std::floor(span * fps + 1e-9)) + 1;
    for (int k = 0; k < count; ++k) {
      const double time = t0 + static_cast<double>(k) / fps;
      int contact = 0;
      const StickFigure f = StickPoints(QAt(tr, time, &hint, &contact), run.lengths);
      const StickPoint points[6] = {f.hip, f.trunk_top, f.knee[0], f.foot[0], f.knee[1], f.foot[1]};
      if (k > 0) {
        t += ',';
        p += ',';
        c += ',';
      }
      t += JsonNumber(time, dec);
      for (int i = 0; i < 6; ++i) {
        p +=
            (i == 0 ? "" : ",") + JsonNumber(points[i].x, dec) + ',' + JsonNumber(points[i].y, dec);
      }
      c += std::to_string(contact);
      if (start < 0 && f.hip.x >= event_x) start = std::max(0, k - static_cast<int>(fps));
      ++frames;
    }
  }
  if (start < 0) {
    start = run.row.outcome == "completed" || frames == 0
                ? 0
                : std::max(0, frames - 1 - static_cast<int>(3.0 * fps));
  }
  std::string obs;
  const Terrain& terrain = run.terrain;
  for (size_t i = 0; i < terrain.obstacles.size(); ++i) {
    const Obstacle& o = terrain.obstacles[i];
    obs += (obs.empty() ? "[" : ",[") + JsonNumber(o.x_start, dec) + ',' +
           JsonNumber(o.length, dec) + ',' + JsonNumber(o.height, dec) + ',' +
           JsonNumber(terrain.ObstacleBase(static_cast<int>(i)), dec) + ']';
  }
  std::string ground;
  const GroundProfile& profile = terrain.ground;
  for (int k = 1; k < profile.num_segments(); ++k) {
    const GroundSegment& g = profile.segment(k);
    ground += (ground.empty() ? "" : ",") + JsonNumber(g.x_start, dec) + ',' +
              JsonNumber(g.height, dec) + ',' + JsonNumber(g.grade, 6);
  }
  // Per step: touchdown time, V_d, V_M, L_step (for the overlay).
  std::string steps;
  for (const Step& s : run.steps) {
    const double v_m = s.t_step > 0.0 ? s.v_m : kNan;
    steps += (steps.empty() ? "" : ",") + JsonNumber(s.t, dec) + ',' + JsonNumber(s.v_d, 3) + ',' +
             JsonNumber(v_m, 3) + ',' + JsonNumber(s.l_step, 3);
  }
  return "{\"fps\":" + JsonNumber(fps, 6) + ",\"frames\":" + std::to_string(frames) +
         ",\"start\":" + std::to_string(start) + ",\"t\":[" + t + "],\"p\":[" + p + "],\"c\":[" +
         (tr.contact.empty() ? "" : c) + "],\"obs\":[" + obs + "],\"g\":[" + ground + "],\"s\":[" +
         steps + "]}";
}
}  // namespace

std::string ReplayHtml(const RunData& run, size_t index, const SuiteReportOptions& options) {
  std::ostringstream html;
  html << "<div class=\"replay\" id=\"replay-" << index << "\"><h4><span class=\"swatch\" "
       << "style=\"background:" << VariantColor(run.row.variant) << "\"></span>"
       << HtmlEscape(RunLabel(run.row)) << " &mdash; run <code>" << HtmlEscape(run.row.run)
       << "</code>, " << HtmlEscape(run.row.outcome) << "</h4>"
       << "<canvas width=\"1000\" height=\"360\"></canvas><div class=\"controls\">"
       << "<button type=\"button\" class=\"play\">Play</button>"
       << "<input type=\"range\" class=\"seek\" min=\"0\" max=\"0\" step=\"1\" value=\"0\" "
          "aria-label=\"time\">"
       << "<label>speed <select class=\"speed\"><option value=\"0.1\">0.1&times;</option>"
          "<option value=\"0.25\">0.25&times;</option><option value=\"0.5\">0.5&times;</option>"
          "<option value=\"1\" selected>1&times;</option><option value=\"2\">2&times;</option>"
          "<option value=\"4\">4&times;</option></select></label>"
       << "<span class=\"time\"></span></div>"
       << "<script type=\"application/json\" class=\"replay-data\">" << ReplayJson(run, options)
       << "</script></div>\n";
  return html.str();
}

std::string SummaryTable(const std::vector<RunData>& runs, const std::vector<ScenarioGroup>& groups,
                         const std::vector<size_t>& which) {
  const int kColumns = 14;
  std::ostringstream html;
  html << "<div class=\"table-wrap\"><table class=\"summary\"><thead><tr>"
          "<th>scenario</th><th>variant</th><th>result</th><th>outcome</th>"
          "<th>duration<br>s</th><th>distance<br>m</th><th>steps</th>"
          "<th>|V<sub>M</sub>&minus;V<sub>d</sub>| m/s<br>mean / final</th>"
          "<th>L<sub>step</sub> m<br>mean (min&ndash;max)</th>"
          "<th>L<sub>step</sub><br>spread mm</th><th>saturation<br>s</th><th>energy<br>J</th>"
          "<th>cost of<br>transport</th><th>wall "
          "s<br>(&times;&nbsp;real&nbsp;time)</th></tr></thead>"
          "<tbody>\n";
  std::vector<size_t> shown = which;
  if (shown.empty()) {
    for (size_t g = 0; g < groups.size(); ++g) shown.push_back(g);
  }
  for (size_t g : shown) {
    const ScenarioGroup& group = groups[g];
    size_t rows = 0;
    for (size_t k : group.runs) rows += runs[k].row.failed.empty() ? 1 : 2;
    for (size_t i = 0; i < group.runs.size(); ++i) {
      const SummaryRow& r = runs[group.runs[i]].row;
      const char* result = r.passed ? "pass" : "fail";
      html << "<tr class=\"" << result << (i == 0 ? " group-start" : "") << "\">";
      if (i == 0) {
        html << "<td class=\"scenario\" rowspan=\"" << rows << "\"><a href=\"#scenario-" << g
             << "\">" << HtmlEscape(group.name) << "</a></td>";
      }
      html << "<td class=\"variant" << (IsMainRun(r) ? "" : " baseline")
           << "\"><span class=\"swatch\" style=\"background:" << VariantColor(r.variant)
           << "\"></span>" << HtmlEscape(RunShortLabel(r)) << "</td><td class=\"status\">"
           << (r.passed ? "&#10003;&nbsp;pass" : "&#10007;&nbsp;fail") << "</td><td class=\"text\">"
           << HtmlEscape(r.outcome);
      if (!r.reason.empty()) html << "<div class=\"reason\">" << HtmlEscape(r.reason) << "</div>";
      html << "</td><td>" << CellNumber(r.duration, 2) << "</td><td>" << CellNumber(r.distance, 2)
           << "</td><td>" << CellNumber(r.steps, 0) << "</td><td>"
           << CellNumber(r.mean_speed_error, 3) << " / " << CellNumber(r.final_speed_error, 3)
           << "</td><td>" << CellNumber(r.l_mean, 3) << " (" << CellNumber(r.l_min, 3) << "&ndash;"
           << CellNumber(r.l_max, 3) << ")</td><td>" << CellNumber(r.l_spread * 1000.0, 1)
           << "</td><td>" << CellNumber(r.saturation, 2) << "</td><td>" << CellNumber(r.energy, 1)
           << "</td><td>" << CellNumber(r.cost_of_transport, 3) << "</td><td>"
           << CellNumber(r.wall, 2) << " (" << CellNumber(r.real_time_factor, 0)
           << "&times;)</td></tr>\n";
      if (!r.failed.empty()) {
        html << "<tr class=\"criteria-row\"><td class=\"criteria\" colspan=\"" << kColumns - 1
             << "\"><b>failed criteria:</b><ul>";
        for (const std::string& f : r.failed) html << "<li>" << HtmlEscape(f) << "</li>";
        html << "</ul></td></tr>\n";
      }
    }
  }
  html << "</tbody></table></div>\n";
  return html.str();
}

namespace {

// Bytes for people: "0 B", "912 B", "37.5 KiB", "2.00 MiB"; "-" when unknown.
std::string MemoryText(double bytes) {
  if (std::isnan(bytes)) return "&ndash;";
  char text[64];
  if (bytes < 1024.0) {
    std::snprintf(text, sizeof text, "%.0f B", bytes);
  } else if (bytes < 1024.0 * 1024.0) {
    std::snprintf(text, sizeof text, "%.1f KiB", bytes / 1024.0);
  } else {
    std::snprintf(text, sizeof text, "%.2f MiB", bytes / (1024.0 * 1024.0));
  }
  return text;
}

// "median (mean)" over n runs.
std::string MedianMean(double median, double mean, int n, int decimals) {
  if (n == 0) return "&ndash;";
  return CellNumber(median, decimals) + " <span class=\"muted\">(" + CellNumber(mean, decimals) +
         ")</span>";
}

}  // namespace

std::string ComparisonTable(const std::vector<const VariantComparison*>& variants) {
  std::ostringstream html;
  html << "<div class=\"table-wrap\"><table class=\"comparison\"><thead><tr>"
          "<th>variant</th><th>runs</th><th>passed</th><th>success rate<br>(95% Wilson)</th>"
          "<th>outcomes</th><th>completed runs:<br>|V<sub>M</sub>&minus;V<sub>d</sub>| m/s, "
          "median (mean)</th><th>completed runs:<br>cost of transport, median (mean)</th>"
          "<th>gait pattern<br>memory</th></tr></thead><tbody>\n";
  for (const VariantComparison* c : variants) {
    std::string outcomes;
    for (const auto& [count, name] : {std::pair<int, const char*>{c->completed, "completed"},
                                      {c->fell, "fell"},
                                      {c->tripped, "tripped"},
                                      {c->stalled, "stalled"},
                                      {c->diverged, "diverged"},
                                      {c->timeout, "timeout"},
                                      {c->other_outcome, "other"}}) {
      if (count > 0)
        outcomes += (outcomes.empty() ? "" : ", ") + std::to_string(count) + " " + name;
    }
    char rate[96];
    std::snprintf(rate, sizeof rate, "%.0f%% <span class=\"muted\">[%.0f, %.0f]</span>",
                  100.0 * c->success_rate, 100.0 * c->ci.low, 100.0 * c->ci.high);
    html << "<tr><td class=\"variant" << (c->role == "baseline" ? " baseline" : "")
         << "\"><span class=\"swatch\" style=\"background:" << VariantColor(c->variant)
         << "\"></span>" << HtmlEscape(VariantShortLabel(c->variant)) << "</td><td>" << c->runs
         << "</td><td>" << c->passed << "</td><td class=\"rate\">" << rate
         << "</td><td class=\"text\">" << outcomes << "</td><td>"
         << MedianMean(c->speed_error_median, c->speed_error_mean, c->speed_error_runs, 3)
         << "</td><td>" << MedianMean(c->cot_median, c->cot_mean, c->cot_runs, 3)
         << "</td><td title=\""
         << (std::isnan(c->pattern_memory_bytes)
                 ? std::string("not recorded")
                 : CellNumber(c->pattern_memory_bytes, 0) + " bytes")
         << "\">" << MemoryText(c->pattern_memory_bytes) << "</td></tr>\n";
  }
  html << "</tbody></table></div>\n";
  for (const VariantComparison* c : variants) {
    if (std::isnan(c->target)) continue;
    char line[256];
    if (c->target_gap >= 0.0) {
      std::snprintf(line, sizeof line, "Target: %s at least %.0f%%: <b>met</b> (%.0f%%).",
                    VariantShortLabel(c->variant).c_str(), 100.0 * c->target,
                    100.0 * c->success_rate);
    } else {
      std::snprintf(line, sizeof line,
                    "Target: %s at least %.0f%%: <b>missed by %.1f points</b> (%.0f%%, 95%% "
                    "interval up to %.0f%%).",
                    VariantShortLabel(c->variant).c_str(), 100.0 * c->target,
                    -100.0 * c->target_gap, 100.0 * c->success_rate, 100.0 * c->ci.high);
    }
    html << "<p class=\"target\">" << line << "</p>\n";
  }
  return html.str();
}

std::string StepsTable(const RunData& run) {
  std::ostringstream html;
  html << "<details><summary>Steps of " << HtmlEscape(RunLabel(run.row)) << " (" << run.steps.size()
       << ")</summary><div class=\"table-wrap\"><table><thead><tr>"
       << "<th>step</th><th>leg</th><th>t<br>s</th><th>V<sub>d</sub><br>m/s</th>"
       << "<th>V<sub>M</sub><br>m/s</th><th>L<sub>step</sub><br>m</th>"
       << "<th>t<sub>step</sub><br>s</th><th>d<sub>obs</sub><br>m</th>"
       << "<th>q<sub>0</sub><sup>d</sup><br>deg</th>";
  for (const std::string& w : run.weight_names) html << "<th>" << HtmlEscape(w) << "</th>";
  html << "<th>rules fired</th></tr></thead><tbody>";
  for (const Step& s : run.steps) {
    html << "<tr><td>" << s.step << "</td><td>" << s.leg << "</td><td>" << CellNumber(s.t, 2)
         << "</td><td>" << CellNumber(s.v_d, 3) << "</td><td>" << CellNumber(s.v_m, 3)
         << "</td><td>" << CellNumber(s.l_step, 3) << "</td><td>" << CellNumber(s.t_step, 3)
         << "</td><td>" << CellNumber(s.d_obs, 3) << "</td><td>" << CellNumber(s.q0_d_deg, 1)
         << "</td>";
    for (double w : s.w) html << "<td>" << CellNumber(w, 3) << "</td>";
    html << "<td class=\"text\">" << HtmlEscape(s.rules) << "</td></tr>";
  }
  html << "</tbody></table></div></details>\n";
  return html.str();
}

std::string TerrainText(const Terrain& terrain) {
  const std::vector<Obstacle>& obstacles = terrain.obstacles;
  const std::vector<SlopeBreak>& breaks = terrain.ground.breaks();
  if (obstacles.empty() && breaks.empty()) return "flat ground";
  std::string out;
  if (!breaks.empty()) {
    out = "ground flat, then";
    for (size_t k = 0; k < breaks.size(); ++k) {
      const double deg = breaks[k].slope * 180.0 / M_PI;
      char buffer[160];
      if (deg == 0.0) {
        std::snprintf(buffer, sizeof buffer, "%s flat from x = %.2f m", k == 0 ? "" : ",",
                      breaks[k].x_start);
      } else {
        std::snprintf(buffer, sizeof buffer, "%s %s %.1f&deg; from x = %.2f m", k == 0 ? "" : ",",
                      deg < 0.0 ? "up" : "down", std::abs(deg), breaks[k].x_start);
      }
      out += buffer;
      if (breaks[k].rise != 0.0) {
        std::snprintf(buffer, sizeof buffer, " after a step %s %.1f cm",
                      breaks[k].rise > 0.0 ? "up" : "down", std::abs(breaks[k].rise) * 100.0);
        out += buffer;
      }
    }
    if (!obstacles.empty()) out += "; ";
  }
  if (obstacles.empty()) return out;
  out +=
      std::to_string(obstacles.size()) + (obstacles.size() == 1 ? " obstacle: " : " obstacles: ");
  for (size_t k = 0; k < obstacles.size(); ++k) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "%sx = %.2f&ndash;%.2f m, %.0f mm high",
                  k == 0 ? "" : "; ", obstacles[k].x_start, obstacles[k].x_end(),
                  obstacles[k].height * 1000.0);
    out += buffer;
  }
  return out;
}

}  // namespace report_internal
}  // namespace rabbit
