#include "hydra_multi/station/bandwidth.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>
#include <thread>

#include "hydra_multi/core/svg_chart.h"

namespace hydra_multi {

void BandwidthLedger::add(const RobotUpdate& update, size_t wire_bytes) {
  updates_[update.robot].emplace_back(update, wire_bytes);
}

std::vector<UpdateBandwidth> BandwidthLedger::robotRows(
    RobotId robot, const std::vector<std::pair<RobotUpdate, size_t>>& arrived) const {
  std::vector<UpdateBandwidth> rows;
  std::vector<const std::pair<RobotUpdate, size_t>*> ordered;
  for (const auto& entry : arrived) ordered.push_back(&entry);
  std::stable_sort(ordered.begin(), ordered.end(), [](const auto* a, const auto* b) {
    return a->first.sequence != b->first.sequence ? a->first.sequence < b->first.sequence
                                                  : !a->first.is_snapshot && b->first.is_snapshot;
  });
  RobotStreamState map;
  bool broken = false;  // an update the map could not take; until the next snapshot
  for (const auto* entry : ordered) {
    const RobotUpdate* u = &entry->first;
    UpdateBandwidth row;
    row.robot = robot;
    row.sequence = u->sequence;
    row.time_ns = u->time_ns;
    row.snapshot = u->is_snapshot;
    row.parts = io::robotUpdateBytes(*u);
    row.record_bytes = row.parts.total() + framing_bytes_;
    row.wire_bytes = entry->second > 0 ? entry->second : row.record_bytes;
    if ((!broken || u->is_snapshot) && map.add(*u).ok()) {
      broken = false;
      row.full_resend_bytes = io::robotUpdateBytes(map.snapshot()).total() + framing_bytes_;
    } else {
      broken = true;
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<UpdateBandwidth> BandwidthLedger::rows() const {
  // Each robot's map is replayed on its own: the robots share the machine's cores.
  std::vector<const std::pair<const RobotId, std::vector<std::pair<RobotUpdate, size_t>>>*> robots;
  for (const auto& entry : updates_) robots.push_back(&entry);
  std::vector<std::vector<UpdateBandwidth>> per_robot(robots.size());
  std::atomic<size_t> next{0};
  const auto work = [&] {
    for (size_t i = next++; i < robots.size(); i = next++)
      per_robot[i] = robotRows(robots[i]->first, robots[i]->second);
  };
  const size_t workers =
      std::min<size_t>(robots.size(), std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> threads;
  for (size_t t = 1; t < workers; ++t) threads.emplace_back(work);
  work();  // (returns at once without robots)
  for (std::thread& t : threads) t.join();
  std::vector<UpdateBandwidth> rows;
  for (std::vector<UpdateBandwidth>& robot : per_robot) {
    for (UpdateBandwidth& row : robot) rows.push_back(std::move(row));
  }
  return rows;
}

std::map<RobotId, RobotBandwidth> bandwidthTotals(const std::vector<UpdateBandwidth>& rows) {
  std::map<RobotId, RobotBandwidth> totals;
  for (const UpdateBandwidth& row : rows) {
    RobotBandwidth& t = totals[row.robot];
    ++t.updates;
    t.wire_bytes += row.wire_bytes;
    t.record_bytes += row.record_bytes;
    if (row.full_resend_bytes)
      t.full_resend_bytes += *row.full_resend_bytes;
    else
      ++t.without_full_resend;
  }
  return totals;
}

RobotBandwidth teamBandwidth(const std::map<RobotId, RobotBandwidth>& robots) {
  RobotBandwidth team;
  for (const auto& [robot, t] : robots) {
    team.updates += t.updates;
    team.wire_bytes += t.wire_bytes;
    team.record_bytes += t.record_bytes;
    team.full_resend_bytes += t.full_resend_bytes;
    team.without_full_resend += t.without_full_resend;
  }
  return team;
}

double fullResendRatio(const RobotBandwidth& t) {
  return t.record_bytes > 0 ? double(t.full_resend_bytes) / double(t.record_bytes) : 0.0;
}

std::string bandwidthCsv(const std::vector<UpdateBandwidth>& rows) {
  std::ostringstream csv;
  csv << "robot,sequence,time_s,kind,wire_bytes,record_bytes,header_bytes,nodes_edges_bytes,mesh_"
         "bytes,"
         "pose_graph_bytes,deformation_bytes,descriptor_bytes,full_resend_bytes\n";
  for (const UpdateBandwidth& r : rows) {
    csv << r.robot.str() << ',' << r.sequence << ',' << svg::fixed(double(r.time_ns) * 1e-9, 3)
        << ',' << (r.snapshot ? "snapshot" : "delta") << ',' << r.wire_bytes << ','
        << r.record_bytes << ',' << r.parts.header << ',' << r.parts.nodes_edges << ','
        << r.parts.mesh << ',' << r.parts.pose_graph << ',' << r.parts.deformation << ','
        << r.parts.descriptors << ','
        << (r.full_resend_bytes ? std::to_string(*r.full_resend_bytes) : std::string()) << '\n';
  }
  return csv.str();
}

std::string bandwidthSvg(const std::vector<UpdateBandwidth>& rows) {
  const double width = 720, height = 420, left = 70, right = 190, top = 40, bottom = 55;
  const double plot_w = width - left - right, plot_h = height - top - bottom;
  // Cumulative MB per robot, ours and as full resends, against robot time from the first update.
  struct Series {
    std::vector<std::pair<double, double>> ours, wire, full;
  };
  std::map<RobotId, Series> series;
  int64_t t0 = rows.empty() ? 0 : rows.front().time_ns;
  for (const UpdateBandwidth& r : rows) t0 = std::min(t0, r.time_ns);
  double t_max = 0.0, mb_max = 0.0, mb_min = 1e300;
  struct Sums {
    double ours = 0.0, wire = 0.0, full = 0.0;  // MB
  };
  std::map<RobotId, Sums> sums;
  bool compressed = false;
  for (const UpdateBandwidth& r : rows) {
    auto& [ours, wire, full] = sums[r.robot];
    const double t = double(r.time_ns - t0) * 1e-9;
    ours += double(r.record_bytes) / 1e6;
    wire += double(r.wire_bytes) / 1e6;
    compressed |= r.wire_bytes != r.record_bytes;
    series[r.robot].ours.emplace_back(t, ours);
    series[r.robot].wire.emplace_back(t, wire);
    if (r.full_resend_bytes) {
      full += double(*r.full_resend_bytes) / 1e6;
      series[r.robot].full.emplace_back(t, full);
    }
    t_max = std::max(t_max, t);
    mb_max = std::max({mb_max, ours, full});
    mb_min = std::min({mb_min, ours, wire});
  }
  const double x_max = svg::niceCeiling(t_max);
  const double decade_lo = std::floor(std::log10(std::max(mb_min, 1e-6)));
  const double decade_hi = std::max(decade_lo + 1.0, std::ceil(std::log10(std::max(mb_max, 1e-6))));
  const auto X = [&](double v) { return left + plot_w * std::clamp(v / x_max, 0.0, 1.0); };
  const auto Y = [&](double mb) {
    const double d = (std::log10(std::max(mb, 1e-12)) - decade_lo) / (decade_hi - decade_lo);
    return top + plot_h * (1.0 - std::clamp(d, 0.0, 1.0));
  };
  std::ostringstream out;
  out << svg::header(width, height, "Bandwidth: our updates against full resends (cumulative)");
  for (double d = decade_lo; d <= decade_hi + 1e-9; d += 1.0) {
    const double mb = std::pow(10.0, d);
    out << "<line x1=\"" << left << "\" x2=\"" << left + plot_w << "\" y1=\"" << Y(mb) << "\" y2=\""
        << Y(mb) << "\" stroke=\"#ddd\"/><text x=\"" << left - 6 << "\" y=\"" << Y(mb) + 4
        << "\" text-anchor=\"end\">" << svg::fixed(mb, d < 0 ? int(-d) : 0) << "</text>\n";
  }
  for (int t = 0; t <= 5; ++t) {
    const double xv = x_max * t / 5.0;
    out << "<text x=\"" << X(xv) << "\" y=\"" << top + plot_h + 18 << "\" text-anchor=\"middle\">"
        << svg::fixed(xv, 0) << "</text>\n";
  }
  out << "<text x=\"" << left + plot_w / 2 << "\" y=\"" << height - 12
      << "\" text-anchor=\"middle\">robot time (s)</text>\n"
      << "<text x=\"16\" y=\"" << top + plot_h / 2 << "\" transform=\"rotate(-90 16 "
      << top + plot_h / 2 << ")\" text-anchor=\"middle\">MB sent so far (log scale)</text>\n"
      << "<line x1=\"" << left << "\" x2=\"" << left + plot_w << "\" y1=\"" << top + plot_h
      << "\" y2=\"" << top + plot_h << "\" stroke=\"black\"/><line x1=\"" << left << "\" x2=\""
      << left << "\" y1=\"" << top << "\" y2=\"" << top + plot_h << "\" stroke=\"black\"/>\n";
  // Solid: our updates; dotted: the same on the wire (compressed); dashed: full resends.
  const auto dashes = [](const std::string& kind) {
    return kind == "full"   ? " stroke-dasharray=\"6 4\""
           : kind == "wire" ? " stroke-dasharray=\"2 3\""
                            : "";
  };
  const auto polyline = [&](const std::vector<std::pair<double, double>>& points,
                            const char* colour, const std::string& kind, const std::string& title) {
    out << "<polyline class=\"" << kind << "\" fill=\"none\" stroke=\"" << colour
        << "\" stroke-width=\"2\"" << dashes(kind) << " points=\"";
    for (const auto& [t, mb] : points) out << X(t) << ',' << Y(mb) << ' ';
    out << "\"><title>" << svg::escape(title) << "</title></polyline>\n";
  };
  const auto legend = [&](double y, const char* colour, const std::string& kind,
                          const std::string& text) {
    out << "<line x1=\"" << left + plot_w + 12 << "\" x2=\"" << left + plot_w + 36 << "\" y1=\""
        << y - 4 << "\" y2=\"" << y - 4 << "\" stroke=\"" << colour << "\" stroke-width=\"2\""
        << dashes(kind) << "/><text x=\"" << left + plot_w + 42 << "\" y=\"" << y << "\">"
        << svg::escape(text) << "</text>\n";
  };
  size_t k = 0;
  const double rows_per_robot = compressed ? 3.0 : 2.0;
  for (const auto& [robot, s] : series) {
    const char* colour = svg::colour(k);
    const Sums& sum = sums[robot];
    const std::string name = "robot " + robot.str();
    polyline(s.ours, colour, "ours", name + ": our updates, " + svg::fixed(sum.ours, 2) + " MB");
    if (compressed)
      polyline(s.wire, colour, "wire", name + ": on the wire, " + svg::fixed(sum.wire, 2) + " MB");
    polyline(s.full, colour, "full", name + ": full resends, " + svg::fixed(sum.full, 1) + " MB");
    const double ly = top + 10 + (16 * rows_per_robot + 8) * double(k);
    legend(ly, colour, "ours", name + ": " + svg::fixed(sum.ours, 2) + " MB");
    if (compressed) legend(ly + 16, colour, "wire", "zstd: " + svg::fixed(sum.wire, 2) + " MB");
    legend(ly + 16 * (rows_per_robot - 1), colour, "full",
           "full resend: " + svg::fixed(sum.full, 1) + " MB");
    ++k;
  }
  out << "</svg>\n";
  return out.str();
}

}  // namespace hydra_multi
