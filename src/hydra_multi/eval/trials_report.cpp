#include "hydra_multi/eval/trials_report.h"

#include "hydra_multi/core/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace hydra_multi {
namespace {

using svg::escape;
using svg::fixed;
using svg::niceCeiling;

}  // namespace

std::optional<MeanStd> summarize(const std::vector<TrialRun>& runs, const std::string& method,
                                 const std::string& metric) {
  std::vector<double> values;
  for (const TrialRun& run : runs) {
    if (run.method != method) continue;
    const auto it = run.metrics.find(metric);
    if (it != run.metrics.end() && std::isfinite(it->second)) values.push_back(it->second);
  }
  if (values.empty()) return std::nullopt;
  MeanStd s;
  s.count = values.size();
  for (const double v : values) s.mean += v;
  s.mean /= double(values.size());
  if (values.size() > 1) {
    double sq = 0.0;
    for (const double v : values) sq += (v - s.mean) * (v - s.mean);
    s.std = std::sqrt(sq / double(values.size() - 1));
  }
  return s;
}

std::string markdownTable(const std::vector<TrialRun>& runs,
                          const std::vector<std::string>& methods,
                          const std::vector<TableColumn>& columns) {
  std::ostringstream out;
  out << "| method |";
  for (const TableColumn& c : columns) out << " " << c.heading << " |";
  out << " runs |\n|---|";
  for (size_t i = 0; i < columns.size(); ++i) out << "---|";
  out << "---|\n";
  for (const std::string& method : methods) {
    size_t count = 0;
    for (const TrialRun& run : runs) count += run.method == method;
    out << "| " << method << " |";
    for (const TableColumn& c : columns) {
      const auto s = summarize(runs, method, c.key);
      out << " "
          << (s ? fixed(s->mean, c.decimals) + " ± " + fixed(s->std, c.decimals)
                : std::string("n/a"))
          << " |";
    }
    out << " " << count << " |\n";
  }
  return out.str();
}

std::string barChartSvg(const std::string& title, const std::vector<TrialRun>& runs,
                        const std::vector<std::string>& methods,
                        const std::vector<TableColumn>& metrics, const std::string& unit) {
  const double width = 640, height = 360, left = 60, right = 150, top = 40, bottom = 50;
  const double plot_w = width - left - right, plot_h = height - top - bottom;
  double top_value = 0.0;
  for (const TableColumn& m : metrics) {
    for (const std::string& method : methods) {
      if (const auto s = summarize(runs, method, m.key))
        top_value = std::max(top_value, s->mean + s->std);
    }
  }
  const double y_max = niceCeiling(top_value);
  const auto y = [&](double v) { return top + plot_h * (1.0 - std::clamp(v / y_max, 0.0, 1.0)); };
  std::ostringstream svg;
  svg << svg::header(width, height, title);
  for (int t = 0; t <= 5; ++t) {
    const double v = y_max * t / 5.0;
    svg << "<line x1=\"" << left << "\" x2=\"" << left + plot_w << "\" y1=\"" << y(v) << "\" y2=\""
        << y(v) << "\" stroke=\"#ddd\"/>"
        << "<text x=\"" << left - 6 << "\" y=\"" << y(v) + 4 << "\" text-anchor=\"end\">"
        << fixed(v, y_max < 5 ? 2 : 0) << "</text>\n";
  }
  svg << "<text x=\"16\" y=\"" << top + plot_h / 2 << "\" transform=\"rotate(-90 16 "
      << top + plot_h / 2 << ")\" text-anchor=\"middle\">" << escape(unit) << "</text>\n";
  const double group_w = plot_w / double(std::max<size_t>(1, metrics.size()));
  const double bar_w = 0.8 * group_w / double(std::max<size_t>(1, methods.size()));
  for (size_t g = 0; g < metrics.size(); ++g) {
    const double x0 = left + g * group_w + 0.1 * group_w;
    for (size_t m = 0; m < methods.size(); ++m) {
      const auto s = summarize(runs, methods[m], metrics[g].key);
      if (!s) continue;
      const double x = x0 + m * bar_w;
      svg << "<rect class=\"bar\" x=\"" << x << "\" y=\"" << y(s->mean) << "\" width=\""
          << bar_w * 0.9 << "\" height=\"" << top + plot_h - y(s->mean) << "\" fill=\""
          << svg::colour(m) << "\"><title>" << escape(methods[m]) << " "
          << escape(metrics[g].heading) << ": " << fixed(s->mean, metrics[g].decimals) << " ± "
          << fixed(s->std, metrics[g].decimals) << "</title></rect>\n";
      const double cx = x + bar_w * 0.45;
      svg << "<line x1=\"" << cx << "\" x2=\"" << cx << "\" y1=\"" << y(s->mean - s->std)
          << "\" y2=\"" << y(s->mean + s->std) << "\" stroke=\"black\"/>\n";
    }
    svg << "<text x=\"" << left + (g + 0.5) * group_w << "\" y=\"" << top + plot_h + 18
        << "\" text-anchor=\"middle\">" << escape(metrics[g].heading) << "</text>\n";
  }
  svg << "<line x1=\"" << left << "\" x2=\"" << left + plot_w << "\" y1=\"" << top + plot_h
      << "\" y2=\"" << top + plot_h << "\" stroke=\"black\"/>\n";
  for (size_t m = 0; m < methods.size(); ++m) {
    const double ly = top + 10 + 20 * m;
    svg << "<rect x=\"" << left + plot_w + 15 << "\" y=\"" << ly - 10 << "\" width=\"12\" "
        << "height=\"12\" fill=\"" << svg::colour(m) << "\"/><text x=\"" << left + plot_w + 32
        << "\" y=\"" << ly << "\">" << escape(methods[m]) << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

std::string backendTimeSvg(const std::vector<TrialRun>& runs,
                           const std::vector<std::string>& methods) {
  const double width = 640, height = 380, left = 70, right = 150, top = 40, bottom = 55;
  const double plot_w = width - left - right, plot_h = height - top - bottom;
  double x_top = 0.0, y_top = 0.0;
  for (const TrialRun& run : runs) {
    for (const TrialRun::Round& r : run.rounds) {
      x_top = std::max(x_top, r.poses);
      y_top = std::max(y_top, r.seconds);
    }
  }
  const double x_max = niceCeiling(x_top), y_max = niceCeiling(y_top);
  const auto X = [&](double v) { return left + plot_w * std::clamp(v / x_max, 0.0, 1.0); };
  const auto Y = [&](double v) { return top + plot_h * (1.0 - std::clamp(v / y_max, 0.0, 1.0)); };
  std::ostringstream svg;
  svg << svg::header(width, height, "Backend time per round against deformation-graph size");
  for (int t = 0; t <= 5; ++t) {
    const double xv = x_max * t / 5.0, yv = y_max * t / 5.0;
    svg << "<line x1=\"" << left << "\" x2=\"" << left + plot_w << "\" y1=\"" << Y(yv) << "\" y2=\""
        << Y(yv) << "\" stroke=\"#ddd\"/><text x=\"" << left - 6 << "\" y=\"" << Y(yv) + 4
        << "\" text-anchor=\"end\">" << fixed(yv, y_max < 5 ? 2 : 0) << "</text>\n"
        << "<text x=\"" << X(xv) << "\" y=\"" << top + plot_h + 18 << "\" text-anchor=\"middle\">"
        << fixed(xv, 0) << "</text>\n";
  }
  svg << "<text x=\"" << left + plot_w / 2 << "\" y=\"" << height - 12
      << "\" text-anchor=\"middle\">deformation-graph poses</text>\n"
      << "<text x=\"16\" y=\"" << top + plot_h / 2 << "\" transform=\"rotate(-90 16 "
      << top + plot_h / 2 << ")\" text-anchor=\"middle\">seconds per round</text>\n"
      << "<line x1=\"" << left << "\" x2=\"" << left + plot_w << "\" y1=\"" << top + plot_h
      << "\" y2=\"" << top + plot_h << "\" stroke=\"black\"/><line x1=\"" << left << "\" x2=\""
      << left << "\" y1=\"" << top << "\" y2=\"" << top + plot_h << "\" stroke=\"black\"/>\n";
  for (size_t m = 0; m < methods.size(); ++m) {
    for (const TrialRun& run : runs) {
      if (run.method != methods[m]) continue;
      for (const TrialRun::Round& r : run.rounds) {
        svg << "<circle class=\"point\" cx=\"" << X(r.poses) << "\" cy=\"" << Y(r.seconds)
            << "\" r=\"3\" fill=\"" << svg::colour(m) << "\" fill-opacity=\"0.7\"><title>"
            << escape(methods[m]) << " seed " << run.seed << ": " << fixed(r.poses, 0) << " poses, "
            << fixed(r.seconds, 3) << " s</title></circle>\n";
      }
    }
    const double ly = top + 10 + 20 * m;
    svg << "<circle cx=\"" << left + plot_w + 21 << "\" cy=\"" << ly - 4 << "\" r=\"5\" fill=\""
        << svg::colour(m) << "\"/><text x=\"" << left + plot_w + 32 << "\" y=\"" << ly << "\">"
        << escape(methods[m]) << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace hydra_multi
