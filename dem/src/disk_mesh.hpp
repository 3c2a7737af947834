#pragma once
// The top plate as a triangulated disk for LIGGGHTS' fix mesh/surface (private to dem/).
//
// Triangulation: concentric rings. Ring k = 1..K has 6k nodes at radius k ρ/K (node j at angle
// 2π j/(6k)); the centre is node 0. Neighbouring rings are stitched by walking both rings in
// angle, which gives 6(2k − 1) triangles between rings k − 1 and k and 6K² in all, with angles
// no smaller than about 30° (LIGGGHTS rejects slivers). The outer ring is a regular 6K-gon
// whose inscribed circle is the plate radius R: ρ = R / cos(π/(6K)), so the mesh covers the
// whole plate and every contact at r <= R hits a face, never an edge of the boundary. The
// disk is flat, so the number of rings only sets the element size: LIGGGHTS' cost of moving a
// mesh grows with its triangle count, its neighbour binning prefers elements not much smaller
// than the particles.
//
// Output: ASCII STL (LIGGGHTS 3.8 reads ASCII STL), normals −z (towards the gap below), nodes
// written with 17 significant digits.
#include <array>
#include <iosfwd>
#include <string_view>
#include <vector>

namespace rheosim::dem::detail {

struct DiskMesh {
  std::vector<std::array<std::array<double, 3>, 3>> triangles;  // corners [m], ordered so the normal is −z
  double outer_radius = 0.0;                                    // ρ [m]
};

// A disk of inscribed radius `radius` > 0 in the plane z = height, `rings` >= 1.
[[nodiscard]] DiskMesh make_disk_mesh(double radius, double height, int rings);

// Writes the mesh as an ASCII STL solid named `name`.
void write_ascii_stl(std::ostream& out, const DiskMesh& mesh, std::string_view name);

}  // namespace rheosim::dem::detail
