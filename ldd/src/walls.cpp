#include "rheosim/ldd/walls.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace rheosim::ldd {
namespace {

using Vec3 = std::array<double, 3>;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
Vec3 unit(const Vec3& a) {
  const double n = norm(a);
  return n > 0 ? scale(a, 1.0 / n) : Vec3{0, 0, 0};
}
Vec3 to_vec3(std::span<const double> x) { return {x[0], x[1], x.size() > 2 ? x[2] : 0.0}; }

// Two unit vectors completing `axis` to an orthonormal basis.
std::pair<Vec3, Vec3> across(const Vec3& axis) {
  const Vec3 helper = std::abs(axis[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = unit(cross(axis, helper));
  return {e1, cross(axis, e1)};
}

// Cells of about `spacing` along `length` (at least one).
int cells(double length, double spacing) { return std::max(1, static_cast<int>(std::lround(length / spacing))); }

// Nearest point of triangle (a, b, c) to p and the feature it lies on: 0 face, 1–3 vertex a/b/c,
// 4–6 edge ab/bc/ca. Voronoi regions of the vertices and edges, then the face (barycentric).
struct Nearest {
  Vec3 point{};
  int feature = 0;
};
Nearest nearest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {a, 1};
  const Vec3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {b, 2};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {add(a, scale(ab, d1 / (d1 - d3))), 4};
  const Vec3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {c, 3};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {add(a, scale(ac, d2 / (d2 - d6))), 6};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {add(b, scale(sub(c, b), w)), 5};
  }
  const double denominator = 1.0 / (va + vb + vc);
  return {add(a, add(scale(ab, vb * denominator), scale(ac, vc * denominator))), 0};
}

// Little-endian reads and writes for binary STL (the format is little-endian by definition).
template <typename T>
T from_little_endian(const char* bytes) {
  std::array<char, sizeof(T)> b{};
  std::memcpy(b.data(), bytes, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(b.begin(), b.end());
  T value;
  std::memcpy(&value, b.data(), sizeof(T));
  return value;
}
template <typename T>
void put_little_endian(std::ostream& os, T value) {
  std::array<char, sizeof(T)> b{};
  std::memcpy(b.data(), &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(b.begin(), b.end());
  os.write(b.data(), static_cast<std::streamsize>(b.size()));
}

// Builds a welded mesh from triangle corner triples; drops degenerate (zero-area) triangles.
class MeshBuilder {
 public:
  void add(const std::array<Vec3, 3>& corners) {
    if (norm(cross(sub(corners[1], corners[0]), sub(corners[2], corners[0]))) <= 0) return;
    std::array<std::size_t, 3> t{};
    for (int k = 0; k < 3; ++k) {
      const auto [it, inserted] = index_.try_emplace(corners[static_cast<std::size_t>(k)], mesh_.vertices.size());
      if (inserted) mesh_.vertices.push_back(corners[static_cast<std::size_t>(k)]);
      t[static_cast<std::size_t>(k)] = it->second;
    }
    mesh_.triangles.push_back(t);
  }
  TriangleMesh take() { return std::move(mesh_); }

 private:
  TriangleMesh mesh_;
  std::map<Vec3, std::size_t> index_;
};

TriangleMesh read_ascii_stl(const std::filesystem::path& file, double factor) {
  std::ifstream in(file);
  if (!in) throw std::invalid_argument(fmt::format("STL file '{}' cannot be opened", file.string()));
  MeshBuilder builder;
  std::string line;
  std::size_t line_number = 0, corner = 0;
  std::array<Vec3, 3> corners{};
  bool in_loop = false;
  const auto fail = [&](const std::string& what) {
    throw std::invalid_argument(fmt::format("STL file '{}', line {}: {}", file.string(), line_number, what));
  };
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream words(line);
    std::string word;
    if (!(words >> word)) continue;
    if (word == "outer") {
      if (in_loop) fail("'outer loop' inside a loop");
      in_loop = true;
      corner = 0;
    } else if (word == "vertex") {
      if (!in_loop) fail("'vertex' outside 'outer loop'");
      if (corner >= 3) fail("more than 3 vertices in a facet (only triangles are valid STL)");
      Vec3 v{};
      for (double& c : v)
        if (!(words >> c) || !std::isfinite(c)) fail("'vertex' needs three finite numbers");
      corners[corner++] = scale(v, factor);
    } else if (word == "endloop") {
      if (!in_loop || corner != 3) fail(fmt::format("a facet with {} vertices (need 3)", corner));
      in_loop = false;
      builder.add(corners);
    } else if (word != "solid" && word != "facet" && word != "endfacet" && word != "endsolid") {
      fail(fmt::format("unexpected keyword '{}'", word));
    }
  }
  if (in_loop) fail("the file ends inside a facet");
  return builder.take();
}

TriangleMesh read_binary_stl(const std::filesystem::path& file, const std::string& bytes, double factor) {
  const std::uint32_t count = from_little_endian<std::uint32_t>(bytes.data() + 80);
  MeshBuilder builder;
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* record = bytes.data() + 84 + 50 * static_cast<std::size_t>(t);
    std::array<Vec3, 3> corners{};
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t d = 0; d < 3; ++d) {
        const float value = from_little_endian<float>(record + 12 + 12 * k + 4 * d);  // after the 12-byte normal
        if (!std::isfinite(value))
          throw std::invalid_argument(
              fmt::format("STL file '{}': triangle {} has a non-finite coordinate", file.string(), t));
        corners[k][d] = factor * static_cast<double>(value);
      }
    builder.add(corners);
  }
  return builder.take();
}

// Every edge must be shared by exactly two triangles, used once in each direction.
void require_closed(const TriangleMesh& mesh, const std::filesystem::path& file) {
  std::map<std::pair<std::size_t, std::size_t>, int> edges;
  for (const auto& t : mesh.triangles)
    for (std::size_t k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  for (const auto& [edge, uses] : edges) {
    const auto reverse = edges.find({edge.second, edge.first});
    if (uses != 1 || reverse == edges.end() || reverse->second != 1)
      throw std::invalid_argument(
          fmt::format("STL file '{}': the surface is not closed and consistently oriented (edge between vertices {} "
                      "and {} is used {} "
                      "time(s) in one direction and {} in the other); inside and outside are undefined",
                      file.string(), edge.first, edge.second, uses, reverse == edges.end() ? 0 : reverse->second));
  }
  if (mesh.triangles.size() < 4)
    throw std::invalid_argument(fmt::format("STL file '{}': fewer than 4 triangles", file.string()));
}

// Keeps points at least min_distance apart (first come, first kept), via a hash grid.
class Thinning {
 public:
  explicit Thinning(double min_distance) : min_(min_distance) {}
  bool accept(const Vec3& x) {
    const auto key = cell_of(x);
    for (long i = -1; i <= 1; ++i)
      for (long j = -1; j <= 1; ++j)
        for (long k = -1; k <= 1; ++k) {
          const auto it = cells_.find({key[0] + i, key[1] + j, key[2] + k});
          if (it == cells_.end()) continue;
          for (const Vec3& y : it->second)
            if (norm(sub(x, y)) < min_) return false;
        }
    cells_[key].push_back(x);
    return true;
  }

 private:
  std::array<long, 3> cell_of(const Vec3& x) const {
    return {std::lround(std::floor(x[0] / min_)), std::lround(std::floor(x[1] / min_)),
            std::lround(std::floor(x[2] / min_))};
  }
  double min_;
  std::map<std::array<long, 3>, std::vector<Vec3>> cells_;
};

}  // namespace

// ------------------------------------------------------------------------------ SolidBoundary

SolidBoundary::SolidBoundary(int dimension, bool fluid_inside, double layer_offset)
    : dimension_(dimension), fluid_inside_(fluid_inside), layer_offset_(layer_offset) {
  if (dimension != 2 && dimension != 3) throw std::invalid_argument("SolidBoundary: dimension must be 2 or 3");
  if (!(layer_offset >= 0)) throw std::invalid_argument("SolidBoundary: layer offset must be >= 0");
}

bool SolidBoundary::distance(std::span<const double> x, double /*t*/, double& distance,
                             std::span<double> normal) const {
  double outward[3] = {0, 0, 0};
  const double s = signed_distance(x, std::span<double>(outward, static_cast<std::size_t>(dimension_)));
  const double sign = fluid_inside_ ? -1.0 : 1.0;
  distance = sign * s + layer_offset_;
  for (std::size_t d = 0; d < static_cast<std::size_t>(dimension_); ++d) normal[d] = sign * outward[d];
  return true;
}

void SolidBoundary::velocity(double /*t*/, std::span<double> v) const { std::fill(v.begin(), v.end(), 0.0); }

// ------------------------------------------------------------------------------ box

BoxBoundary::BoxBoundary(std::vector<double> lower, std::vector<double> upper, bool fluid_inside, double layer_offset)
    : SolidBoundary(static_cast<int>(lower.size()), fluid_inside, layer_offset),
      lower_(std::move(lower)),
      upper_(std::move(upper)) {
  if (upper_.size() != lower_.size()) throw std::invalid_argument("BoxBoundary: lower and upper differ in size");
  for (std::size_t d = 0; d < lower_.size(); ++d)
    if (!(upper_[d] > lower_[d]))
      throw std::invalid_argument("BoxBoundary: upper must exceed lower in every coordinate");
  if (!fluid_inside)
    for (std::size_t d = 0; d < lower_.size(); ++d)
      if (!(upper_[d] - lower_[d] > 2 * layer_offset))
        throw std::invalid_argument("BoxBoundary: an obstacle box must be thicker than its two wall layers");
}

double BoxBoundary::signed_distance(std::span<const double> x, std::span<double> outward) const {
  // q_d = |x_d − c_d| − half_d: outside the box where some q_d > 0.
  const std::size_t dim = lower_.size();
  double q[3] = {0, 0, 0}, side[3] = {0, 0, 0}, outside = 0, largest = -std::numeric_limits<double>::infinity();
  std::size_t largest_axis = 0;
  for (std::size_t d = 0; d < dim; ++d) {
    const double centre = 0.5 * (lower_[d] + upper_[d]), half = 0.5 * (upper_[d] - lower_[d]);
    side[d] = x[d] >= centre ? 1.0 : -1.0;
    q[d] = std::abs(x[d] - centre) - half;
    if (q[d] > 0) outside += q[d] * q[d];
    if (q[d] > largest) {
      largest = q[d];
      largest_axis = d;
    }
  }
  for (std::size_t d = 0; d < dim; ++d) outward[d] = 0.0;
  if (outside > 0) {  // nearest point on a face, edge or corner: the gradient points from it to x
    const double distance = std::sqrt(outside);
    for (std::size_t d = 0; d < dim; ++d) outward[d] = q[d] > 0 ? side[d] * q[d] / distance : 0.0;
    return distance;
  }
  outward[largest_axis] = side[largest_axis];  // inside: the nearest face
  return largest;
}

std::vector<WallNode> BoxBoundary::wall_nodes(double spacing) const {
  // The layer box, grown (container) or shrunk (obstacle) by the layer offset. Nodes at the cell
  // centres of each face, plus edge (3D) and corner nodes where faces meet (corner = true, normal
  // along the bisector).
  const std::size_t dim = lower_.size();
  const double shift = layer_shift();
  std::vector<double> lo(dim), hi(dim);
  std::vector<int> n(dim);
  for (std::size_t d = 0; d < dim; ++d) {
    lo[d] = lower_[d] - shift;
    hi[d] = upper_[d] + shift;
    n[d] = cells(hi[d] - lo[d], spacing);  // intervals between the edge rows at lo and hi
  }
  const double inward = fluid_inside() ? -1.0 : 1.0;  // the fluid-side direction relative to outward
  std::vector<WallNode> nodes;
  // Each axis is free (the points strictly between the edge rows, about Δ apart), or fixed at its
  // lower (−1) or upper (+1) side; at least one axis fixed.
  const std::size_t combinations = dim == 3 ? 27 : 9;
  for (std::size_t code = 0; code < combinations; ++code) {
    int state[3] = {0, 0, 0};
    std::size_t fixed = 0, c = code;
    for (std::size_t d = 0; d < dim; ++d) {
      state[d] = static_cast<int>(c % 3) - 1;
      c /= 3;
      fixed += state[d] != 0 ? 1 : 0;
    }
    if (fixed == 0) continue;
    Vec3 normal{0, 0, 0};
    for (std::size_t d = 0; d < dim; ++d) normal[d] = inward * state[d];
    normal = unit(normal);
    // Iterate over the free axes' cell indices.
    int counts[3] = {1, 1, 1};
    for (std::size_t d = 0; d < dim; ++d)
      if (state[d] == 0) counts[d] = n[d] - 1;
    for (int a = 0; a < counts[0]; ++a)
      for (int b = 0; b < counts[1]; ++b)
        for (int e = 0; e < (dim == 3 ? counts[2] : 1); ++e) {
          const int index[3] = {a, b, e};
          WallNode node;
          for (std::size_t d = 0; d < dim; ++d) {
            if (state[d] < 0)
              node.x[d] = lo[d];
            else if (state[d] > 0)
              node.x[d] = hi[d];
            else
              node.x[d] = lo[d] + (index[d] + 1) * (hi[d] - lo[d]) / n[d];
          }
          node.normal = normal;
          node.corner = fixed >= 2;
          nodes.push_back(node);
        }
  }
  return nodes;
}

// ------------------------------------------------------------------------------ cylinder

CylinderBoundary::CylinderBoundary(std::array<double, 3> base, std::array<double, 3> axis, double radius, double height,
                                   bool fluid_inside, double layer_offset)
    : SolidBoundary(3, fluid_inside, layer_offset), base_(base), axis_(unit(axis)), radius_(radius), height_(height) {
  if (norm(axis) <= 0) throw std::invalid_argument("CylinderBoundary: zero axis");
  if (!(radius > 0 && height > 0)) throw std::invalid_argument("CylinderBoundary: radius and height must be > 0");
  if (!fluid_inside && !(radius > layer_offset && height > 2 * layer_offset))
    throw std::invalid_argument("CylinderBoundary: an obstacle cylinder must be thicker than its wall layers");
  std::tie(e1_, e2_) = across(axis_);
}

double CylinderBoundary::signed_distance(std::span<const double> x, std::span<double> outward) const {
  const Vec3 p = sub(to_vec3(x), base_);
  const double z = dot(p, axis_);
  const Vec3 radial = sub(p, scale(axis_, z));
  const double rho = norm(radial);
  const Vec3 r_hat = rho > 0 ? scale(radial, 1.0 / rho) : e1_;  // on the axis any radial direction
  const double dr = rho - radius_;                              // beyond the mantle
  const bool upper = z > 0.5 * height_;
  const double dz = upper ? z - height_ : -z;  // beyond the nearer cap
  const Vec3 z_hat = upper ? axis_ : scale(axis_, -1.0);
  Vec3 n{};
  double s = 0;
  if (dr > 0 || dz > 0) {
    const double a = std::max(dr, 0.0), b = std::max(dz, 0.0);
    s = std::hypot(a, b);
    n = unit(add(scale(r_hat, a), scale(z_hat, b)));
  } else {
    s = std::max(dr, dz);
    n = dr > dz ? r_hat : z_hat;
  }
  for (std::size_t d = 0; d < 3; ++d) outward[d] = n[d];
  return s;
}

std::vector<WallNode> CylinderBoundary::wall_nodes(double spacing) const {
  // Layer cylinder: radius R ± offset, caps at −offset and H + offset (container) or +offset and
  // H − offset (obstacle). Mantle rings every ~Δ between the caps (staggered by half a node),
  // caps on a Cartesian grid of the cross-section inside the rim, rim rings as corner nodes.
  const double shift = layer_shift(), inward = fluid_inside() ? -1.0 : 1.0;
  const double r = radius_ + shift, z0 = -shift, z1 = height_ + shift;
  std::vector<WallNode> nodes;
  const auto point = [&](double radial_1, double radial_2, double z) {
    return add(base_, add(add(scale(e1_, radial_1), scale(e2_, radial_2)), scale(axis_, z)));
  };
  const int around = std::max(6, static_cast<int>(std::lround(2 * std::numbers::pi * r / spacing)));
  const int rings = cells(z1 - z0, spacing);
  for (int k = 0; k <= rings; ++k) {  // k = 0 and k = rings: the rims at the caps
    const bool rim = k == 0 || k == rings;
    const double z = z0 + k * (z1 - z0) / rings;
    for (int q = 0; q < around; ++q) {
      const double angle = 2 * std::numbers::pi * (q + 0.5 * (k % 2)) / around;
      const Vec3 radial = add(scale(e1_, std::cos(angle)), scale(e2_, std::sin(angle)));
      WallNode node;
      node.x = point(r * std::cos(angle), r * std::sin(angle), z);
      Vec3 normal = scale(radial, inward);
      if (rim) normal = unit(add(normal, scale(axis_, inward * (k == 0 ? -1.0 : 1.0))));
      node.normal = normal;
      node.corner = rim;
      nodes.push_back(node);
    }
  }
  const int m = static_cast<int>(std::ceil(r / spacing));
  for (int cap = 0; cap < 2; ++cap) {
    const double z = cap == 0 ? z0 : z1;
    const Vec3 normal = scale(axis_, inward * (cap == 0 ? -1.0 : 1.0));
    for (int i = -m; i < m; ++i)
      for (int j = -m; j < m; ++j) {
        const double a = (i + 0.5) * spacing, b = (j + 0.5) * spacing;
        if (std::hypot(a, b) > r - 0.5 * spacing) continue;
        nodes.push_back(WallNode{point(a, b, z), normal, false});
      }
  }
  return nodes;
}

// ------------------------------------------------------------------------------ meshes and STL

double TriangleMesh::volume() const {
  double v = 0;
  for (const auto& t : triangles) v += dot(vertices[t[0]], cross(vertices[t[1]], vertices[t[2]])) / 6.0;
  return v;
}

TriangleMesh read_stl(const std::filesystem::path& file, double factor) {
  if (!(factor > 0)) throw std::invalid_argument("read_stl: scale must be > 0");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::invalid_argument(fmt::format("STL file '{}' cannot be opened", file.string()));
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Binary when the size matches its triangle count exactly (binary headers may begin with
  // "solid" too); otherwise ASCII.
  const bool binary =
      bytes.size() >= 84 &&
      bytes.size() == 84 + 50 * static_cast<std::size_t>(from_little_endian<std::uint32_t>(bytes.data() + 80));
  TriangleMesh mesh;
  if (binary) {
    mesh = read_binary_stl(file, bytes, factor);
  } else {
    const auto first = bytes.find_first_not_of(" \t\r\n");
    if (first == std::string::npos || bytes.compare(first, 5, "solid") != 0)
      throw std::invalid_argument(fmt::format(
          "STL file '{}' is neither binary STL (size 84 + 50 × triangle count) nor ASCII STL (starting with 'solid')",
          file.string()));
    mesh = read_ascii_stl(file, factor);
  }
  require_closed(mesh, file);
  if (mesh.volume() < 0)  // wound clockwise: reorient so that normals point out
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

void write_stl_ascii(const std::filesystem::path& file, const TriangleMesh& mesh) {
  std::ofstream out(file);
  out << "solid rheosim\n";
  for (const auto& t : mesh.triangles) {
    const Vec3 n =
        unit(cross(sub(mesh.vertices[t[1]], mesh.vertices[t[0]]), sub(mesh.vertices[t[2]], mesh.vertices[t[0]])));
    out << fmt::format("  facet normal {:.9g} {:.9g} {:.9g}\n    outer loop\n", n[0], n[1], n[2]);
    for (std::size_t k : t) {
      const Vec3& v = mesh.vertices[k];
      out << fmt::format("      vertex {:.17g} {:.17g} {:.17g}\n", v[0], v[1], v[2]);
    }
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid rheosim\n";
  if (!out) throw std::runtime_error(fmt::format("cannot write STL file '{}'", file.string()));
}

void write_stl_binary(const std::filesystem::path& file, const TriangleMesh& mesh) {
  std::ofstream out(file, std::ios::binary);
  std::array<char, 80> header{};
  const std::string title = "rheosim binary STL";
  std::copy(title.begin(), title.end(), header.begin());
  out.write(header.data(), header.size());
  put_little_endian<std::uint32_t>(out, static_cast<std::uint32_t>(mesh.triangles.size()));
  for (const auto& t : mesh.triangles) {
    const Vec3 n =
        unit(cross(sub(mesh.vertices[t[1]], mesh.vertices[t[0]]), sub(mesh.vertices[t[2]], mesh.vertices[t[0]])));
    for (double c : n) put_little_endian<float>(out, static_cast<float>(c));
    for (std::size_t k : t)
      for (double c : mesh.vertices[k]) put_little_endian<float>(out, static_cast<float>(c));
    put_little_endian<std::uint16_t>(out, 0);
  }
  if (!out) throw std::runtime_error(fmt::format("cannot write STL file '{}'", file.string()));
}

TriangleMesh box_mesh(std::array<double, 3> lo, std::array<double, 3> hi) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k)
    m.vertices.push_back({(k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]});
  // Quads with outward counter-clockwise corners, two triangles each.
  const std::size_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

TriangleMesh cylinder_mesh(std::array<double, 3> base, double radius, double height, int segments) {
  if (segments < 3) throw std::invalid_argument("cylinder_mesh: needs at least 3 segments");
  TriangleMesh m;
  const auto s = static_cast<std::size_t>(segments);
  for (std::size_t level = 0; level < 2; ++level)
    for (std::size_t q = 0; q < s; ++q) {
      const double angle = 2 * std::numbers::pi * static_cast<double>(q) / segments;
      m.vertices.push_back({base[0] + radius * std::cos(angle), base[1] + radius * std::sin(angle),
                            base[2] + (level == 0 ? 0.0 : height)});
    }
  m.vertices.push_back(base);                                  // 2s: bottom centre
  m.vertices.push_back({base[0], base[1], base[2] + height});  // 2s + 1: top centre
  for (std::size_t q = 0; q < s; ++q) {
    const std::size_t a = q, b = (q + 1) % s;
    m.triangles.push_back({a, b, s + b});
    m.triangles.push_back({a, s + b, s + a});
    m.triangles.push_back({2 * s, b, a});
    m.triangles.push_back({2 * s + 1, s + a, s + b});
  }
  return m;
}

StlBoundary::StlBoundary(TriangleMesh mesh, bool fluid_inside, double layer_offset)
    : SolidBoundary(3, fluid_inside, layer_offset), mesh_(std::move(mesh)) {
  if (mesh_.triangles.empty()) throw std::invalid_argument("StlBoundary: empty mesh");
  // Angle-weighted pseudo-normals (Bærentzen & Aanæs 2005): faces their own normal, edges the sum
  // of the two faces' normals, vertices the sum of incident face normals weighted by the angle
  // at the vertex. The sign of (x − nearest point)·pseudo-normal is then exact for closed meshes.
  const std::size_t nt = mesh_.triangles.size();
  face_normals_.resize(nt);
  vertex_normals_.assign(mesh_.vertices.size(), Vec3{0, 0, 0});
  std::map<std::pair<std::size_t, std::size_t>, Vec3> edge_sum;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = mesh_.triangles[t];
    const Vec3 n = unit(cross(sub(mesh_.vertices[tri[1]], mesh_.vertices[tri[0]]),
                              sub(mesh_.vertices[tri[2]], mesh_.vertices[tri[0]])));
    face_normals_[t] = n;
    for (std::size_t k = 0; k < 3; ++k) {
      const Vec3& v = mesh_.vertices[tri[k]];
      const Vec3 e1 = unit(sub(mesh_.vertices[tri[(k + 1) % 3]], v)),
                 e2 = unit(sub(mesh_.vertices[tri[(k + 2) % 3]], v));
      const double angle = std::acos(std::clamp(dot(e1, e2), -1.0, 1.0));
      vertex_normals_[tri[k]] = add(vertex_normals_[tri[k]], scale(n, angle));
      const auto key = std::minmax(tri[k], tri[(k + 1) % 3]);
      edge_sum[{key.first, key.second}] = add(edge_sum[{key.first, key.second}], n);
    }
  }
  edge_normals_.resize(nt);
  for (std::size_t t = 0; t < nt; ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto& tri = mesh_.triangles[t];
      const auto key = std::minmax(tri[k], tri[(k + 1) % 3]);
      edge_normals_[t][k] = edge_sum[{key.first, key.second}];
    }
}

double StlBoundary::signed_distance(std::span<const double> x, std::span<double> outward) const {
  const Vec3 p = to_vec3(x);
  double best = std::numeric_limits<double>::infinity();
  Vec3 nearest{};
  Vec3 pseudo{};
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const auto& tri = mesh_.triangles[t];
    const Nearest q = nearest_on_triangle(p, mesh_.vertices[tri[0]], mesh_.vertices[tri[1]], mesh_.vertices[tri[2]]);
    const Vec3 offset = sub(p, q.point);
    const double d2 = dot(offset, offset);
    if (!(d2 < best)) continue;
    best = d2;
    nearest = q.point;
    if (q.feature == 0)
      pseudo = face_normals_[t];
    else if (q.feature <= 3)
      pseudo = vertex_normals_[tri[static_cast<std::size_t>(q.feature - 1)]];
    else
      pseudo = edge_normals_[t][static_cast<std::size_t>(q.feature - 4)];  // ab, bc, ca = edges 0, 1, 2
  }
  const double distance = std::sqrt(best);
  const Vec3 offset = sub(p, nearest);
  const double sign = dot(offset, pseudo) >= 0 ? 1.0 : -1.0;
  // Outward normal: along x − nearest point (the gradient of s) away from the surface, the
  // feature's pseudo-normal on it.
  const Vec3 n = distance > 1e-12 ? scale(offset, sign / distance) : unit(pseudo);
  for (std::size_t d = 0; d < 3; ++d) outward[d] = n[d];
  return sign * distance;
}

std::vector<WallNode> StlBoundary::wall_nodes(double spacing) const {
  // Points on each triangle on a barycentric grid finer than Δ, moved off the surface by the layer
  // offset along the face normal (into the wall material), then thinned to ≥ 0.7 Δ apart.
  const double inward = fluid_inside() ? -1.0 : 1.0;
  Thinning thinning(0.7 * spacing);
  std::vector<WallNode> nodes;
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const auto& tri = mesh_.triangles[t];
    const Vec3 &a = mesh_.vertices[tri[0]], &b = mesh_.vertices[tri[1]], &c = mesh_.vertices[tri[2]];
    const double longest = std::max({norm(sub(b, a)), norm(sub(c, b)), norm(sub(a, c))});
    const int n = std::max(1, static_cast<int>(std::ceil(longest / (0.5 * spacing))));
    const Vec3 shift = scale(face_normals_[t], layer_shift());
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
        const Vec3 x = add(add(a, add(scale(sub(b, a), u), scale(sub(c, a), v))), shift);
        if (!thinning.accept(x)) continue;
        nodes.push_back(WallNode{x, scale(face_normals_[t], inward), false});
      }
  }
  return nodes;
}

// ------------------------------------------------------------------------------ registry

namespace {

// A plane's wall nodes: a Δ-lattice of the plane clipped to the region box, Δ/2 behind the
// physical plane (the same convention as the scenes' floors).
BuiltWall make_plane(const ldd::WallSettings& spec, int dimension, double spacing, std::span<const double> lower,
                     std::span<const double> upper) {
  const auto dim = static_cast<std::size_t>(dimension);
  const Vec3 n = unit(to_vec3(spec.normal));
  Vec3 layer_point = sub(to_vec3(spec.point), scale(n, 0.5 * spacing));
  BuiltWall built;
  built.boundary = std::make_shared<PlaneBoundary>(
      std::vector<double>(layer_point.begin(), layer_point.begin() + static_cast<std::ptrdiff_t>(dim)),
      std::vector<double>(n.begin(), n.begin() + static_cast<std::ptrdiff_t>(dim)));
  Vec3 e1{}, e2{};
  if (dim == 2)
    e1 = {-n[1], n[0], 0};
  else
    std::tie(e1, e2) = across(n);
  // Project the region's corners onto the plane's axes to bound the lattice.
  double extent = 0;
  for (std::size_t d = 0; d < dim; ++d)
    extent = std::max({extent, std::abs(lower[d] - layer_point[d]), std::abs(upper[d] - layer_point[d])});
  const int m = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(dim)) * extent / spacing));
  for (int i = -m; i <= m; ++i)
    for (int j = (dim == 3 ? -m : 0); j <= (dim == 3 ? m : 0); ++j) {
      const Vec3 x = add(layer_point, add(scale(e1, i * spacing), scale(e2, j * spacing)));
      bool in_region = true;
      for (std::size_t d = 0; d < dim; ++d) in_region = in_region && x[d] >= lower[d] && x[d] <= upper[d];
      if (in_region) built.nodes.push_back(WallNode{x, n, false});
    }
  return built;
}

template <typename Shape, typename... Args>
BuiltWall make_solid(double spacing, Args&&... args) {
  auto shape = std::make_shared<const Shape>(std::forward<Args>(args)...);
  BuiltWall built;
  built.nodes = shape->wall_nodes(spacing);
  built.boundary = std::move(shape);
  return built;
}

using WallFactory = BuiltWall (*)(const ldd::WallSettings&, int, double, std::span<const double>,
                                  std::span<const double>);

struct RegistryEntry {
  const char* name;
  WallFactory make;
};

// The registry: one entry per wall type (the case parser validates each type's keys).
constexpr RegistryEntry registry[] = {
    {"plane", &make_plane},
    {"box",
     [](const ldd::WallSettings& w, int, double dx, std::span<const double>, std::span<const double>) {
       return make_solid<BoxBoundary>(dx, w.lower, w.upper, w.fluid_inside, 0.5 * dx);
     }},
    {"cylinder",
     [](const ldd::WallSettings& w, int, double dx, std::span<const double>, std::span<const double>) {
       return make_solid<CylinderBoundary>(dx, to_vec3(w.base), to_vec3(w.axis), w.radius, w.height, w.fluid_inside,
                                           0.5 * dx);
     }},
    {"stl",
     [](const ldd::WallSettings& w, int, double dx, std::span<const double>, std::span<const double>) {
       return make_solid<StlBoundary>(dx, read_stl(w.file, w.scale), w.fluid_inside, 0.5 * dx);
     }},
};

}  // namespace

BuiltWall make_wall(const ldd::WallSettings& spec, int dimension, double spacing, std::span<const double> region_lower,
                    std::span<const double> region_upper) {
  if (!(spacing > 0)) throw std::invalid_argument("make_wall: spacing must be > 0");
  const auto dim = static_cast<std::size_t>(dimension);
  if (region_lower.size() < dim || region_upper.size() < dim)
    throw std::invalid_argument("make_wall: the region needs one bound per dimension");
  for (const RegistryEntry& entry : registry)
    if (spec.type == entry.name) return entry.make(spec, dimension, spacing, region_lower, region_upper);
  throw std::invalid_argument(
      fmt::format("unknown LDD wall type '{}', expected one of: {}", spec.type, fmt::join(wall_types(), ", ")));
}

std::vector<std::string> wall_types() {
  std::vector<std::string> names;
  for (const RegistryEntry& entry : registry) names.emplace_back(entry.name);
  return names;
}

}  // namespace rheosim::ldd
