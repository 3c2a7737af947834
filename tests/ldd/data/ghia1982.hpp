// Ghia, Ghia & Shin, J. Comput. Phys. 48 (1982) 387–411, Tables I–II: the lid-driven cavity's
// centre-line velocities at Re = 100 and 1000 (ghia1982_centerlines.csv next to this file),
// read by the cavity validation test and by bench_ldd's accuracy study.
#pragma once

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace rheosim::ldd::reference {

struct GhiaPoint {
  char line;          // 'u': vertical centre line (coordinate y), 'v': horizontal (coordinate x)
  double coordinate;  // y or x, normalised
  double re100, re1000;
};

inline std::vector<GhiaPoint> ghia1982(const std::string& source_dir) {
  const std::string path = source_dir + "/tests/ldd/data/ghia1982_centerlines.csv";
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::vector<GhiaPoint> points;
  std::string row;
  while (std::getline(in, row)) {
    if (row.empty() || row[0] == '#') continue;
    std::replace(row.begin(), row.end(), ',', ' ');
    std::istringstream fields(row);
    GhiaPoint p{};
    fields >> p.line >> p.coordinate >> p.re100 >> p.re1000;
    points.push_back(p);
  }
  return points;
}

// Ghia's points as cavity fractions (x, y): u points on x = 0.5, v points on y = 0.5.
inline std::vector<double> ghia_probe_fractions(const std::vector<GhiaPoint>& points) {
  std::vector<double> f;
  for (const auto& p : points) {
    if (p.line == 'u')
      f.insert(f.end(), {0.5, p.coordinate});
    else
      f.insert(f.end(), {p.coordinate, 0.5});
  }
  return f;
}

}  // namespace rheosim::ldd::reference
