// The station under load (issue 23, item 4): for each run folder of `station` fed by robot
// processes (scripts/bench_load.sh: timing.csv, load.csv, station.json, bench.json), the latency
// of each update from its arrival on the ingest queue to the end of its processing (median, p99,
// max), the queue's length over the robots' mission (max, mean, at each tenth of it, its slope over
// the second half) and how long it took to drain after the robots ended, the backend's rounds, the
// station's peak memory and CPU, and whether it kept up: the queue drained within 5 s of the
// robots' end and did not grow over the second half of the mission (slope under 1 update a
// minute), with p99 latency against the 50 ms apart.
//
//   bench_load LABEL=RUN_DIR [LABEL=RUN_DIR ...]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Sample {
  double wall_s = 0, queued = 0, rss_mb = 0, cpu_s = 0;
};

struct Team {
  std::string label;
  nlohmann::json station, bench;
  std::vector<double> latency_ms, processing_ms, rounds_ms;
  std::vector<Sample> load;
};

std::vector<std::string> cellsOf(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * v.size())) - 1);
  return v[q <= 0.0 ? 0 : k];
}

bool readJson(const std::string& path, nlohmann::json& out, std::string& error) {
  std::ifstream in(path);
  out = nlohmann::json::parse(in, nullptr, false);
  if (out.is_discarded() || !out.is_object()) {
    error = path + ": not a JSON object (did the run finish?)";
    return false;
  }
  return true;
}

bool readTeam(const std::string& label, const std::string& dir, Team& team, std::string& error) {
  team.label = label;
  if (!readJson(dir + "/station.json", team.station, error)) return false;
  if (!readJson(dir + "/bench.json", team.bench, error)) return false;
  std::ifstream timing(dir + "/timing.csv");
  std::string line;
  std::getline(timing, line);
  if (cellsOf(line).size() < 19 || cellsOf(line)[18] != "queue_ms") {
    error = dir + "/timing.csv: no queue_ms column (a station of an older build?)";
    return false;
  }
  while (std::getline(timing, line)) {
    const std::vector<std::string> cells = cellsOf(line);
    if (cells.size() >= 19 && cells[0] == "update") {
      const double ms = std::stod(cells[5]), queue = std::stod(cells[18]);
      team.processing_ms.push_back(ms);
      team.latency_ms.push_back(ms + queue);
    } else if (cells.size() >= 18 && cells[0] == "backend" && cells[17] != "1") {
      team.rounds_ms.push_back(std::stod(cells[5]));
    }
  }
  std::ifstream load(dir + "/load.csv");
  std::getline(load, line);
  while (std::getline(load, line)) {
    const std::vector<std::string> c = cellsOf(line);
    if (c.size() < 5) continue;
    team.load.push_back(
        {std::stod(c[0]), std::stod(c[1]), std::stod(c[2]), std::stod(c[3]) + std::stod(c[4])});
  }
  if (team.latency_ms.empty() || team.load.empty()) {
    error = dir + ": no updates in timing.csv or no samples in load.csv";
    return false;
  }
  return true;
}

// Least-squares slope of the queue's length against time (updates per second).
double slope(const std::vector<Sample>& samples) {
  if (samples.size() < 2) return 0.0;
  double mt = 0, mq = 0;
  for (const Sample& s : samples) {
    mt += s.wall_s;
    mq += s.queued;
  }
  mt /= samples.size();
  mq /= samples.size();
  double num = 0, den = 0;
  for (const Sample& s : samples) {
    num += (s.wall_s - mt) * (s.queued - mq);
    den += (s.wall_s - mt) * (s.wall_s - mt);
  }
  return den > 0 ? num / den : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_load LABEL=RUN_DIR [LABEL=RUN_DIR ...]\n");
    return 2;
  }
  std::vector<Team> teams;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const size_t eq = arg.find('=');
    if (eq == std::string::npos) {
      std::fprintf(stderr, "bench_load: '%s' is not LABEL=RUN_DIR\n", arg.c_str());
      return 2;
    }
    Team team;
    std::string error;
    if (!readTeam(arg.substr(0, eq), arg.substr(eq + 1), team, error)) {
      std::fprintf(stderr, "bench_load: %s\n", error.c_str());
      return 1;
    }
    teams.push_back(std::move(team));
  }
  std::printf(
      "| team | updates | latency median / p99 / max (ms) | processing median (ms) | queue max / "
      "mean | queue slope, 2nd half (per min) | drained after robots (s) | backend rounds, "
      "median / max (s) | peak memory (MB), per robot | CPU (cores) | kept up | p99 <= 50 ms |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (const Team& t : teams) {
    const double robots = t.bench.value("robots", 0.0);
    const double end_s = t.bench.value("robots_end_s", 0.0);  // on load.csv's clock
    std::vector<Sample> mission, second_half;
    double queue_max = 0, queue_sum = 0;
    for (const Sample& s : t.load) {
      if (s.wall_s > end_s) continue;
      mission.push_back(s);
      queue_max = std::max(queue_max, s.queued);
      queue_sum += s.queued;
      if (s.wall_s >= end_s / 2) second_half.push_back(s);
    }
    double drained_s = std::nan("");
    for (const Sample& s : t.load) {
      if (s.wall_s >= end_s && s.queued == 0) {
        drained_s = s.wall_s - end_s;
        break;
      }
    }
    const double per_min = 60.0 * slope(second_half);
    const Sample& last = t.load.back();
    const double peak_mb = t.station.value("peak_memory_mb", std::nan(""));
    const double p99 = quantile(t.latency_ms, 0.99);
    const bool kept_up = !std::isnan(drained_s) && drained_s <= 5.0 && per_min < 1.0;
    char drained[32] = "never";
    if (!std::isnan(drained_s)) std::snprintf(drained, sizeof(drained), "%.1f", drained_s);
    std::printf(
        "| %s | %zu | %.1f / %.1f / %.1f | %.1f | %.0f / %.1f | %+.2f | %s | %zu, %.2f / %.2f | "
        "%.0f, %.0f | %.2f | %s | %s |\n",
        t.label.c_str(), t.latency_ms.size(), quantile(t.latency_ms, 0.5), p99,
        quantile(t.latency_ms, 1.0), quantile(t.processing_ms, 0.5), queue_max,
        mission.empty() ? 0.0 : queue_sum / mission.size(), per_min, drained, t.rounds_ms.size(),
        quantile(t.rounds_ms, 0.5) / 1e3, quantile(t.rounds_ms, 1.0) / 1e3, peak_mb,
        robots > 0 ? peak_mb / robots : 0.0, last.wall_s > 0 ? last.cpu_s / last.wall_s : 0,
        kept_up ? "yes" : "no", p99 <= 50.0 ? "yes" : "no");
  }
  std::printf(
      "\nThe ingest queue (updates waiting) at each tenth of the robots' mission:\n\n| team |");
  for (int k = 1; k <= 10; ++k) std::printf(" %d %% |", 10 * k);
  std::printf("\n| --- |");
  for (int k = 1; k <= 10; ++k) std::printf(" --- |");
  std::printf("\n");
  for (const Team& t : teams) {
    const double end_s = t.bench.value("robots_end_s", 0.0);
    std::printf("| %s |", t.label.c_str());
    for (int k = 1; k <= 10; ++k) {
      const double at = end_s * k / 10.0;
      const Sample* nearest = &t.load.front();
      for (const Sample& s : t.load)
        if (std::abs(s.wall_s - at) < std::abs(nearest->wall_s - at)) nearest = &s;
      std::printf(" %.0f |", nearest->queued);
    }
    std::printf("\n");
  }
  return 0;
}
