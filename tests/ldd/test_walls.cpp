// Walls of free-surface LDD scenes: box and capped-cylinder signed distances and normals
// against closed forms, STL meshes (ASCII and binary) of the same shapes giving the same
// distances, wall-node layers on their boundaries, the case-file entries validated at the edge,
// and a small slump in a cylindrical container whose fluid stays inside.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "rheosim/core/error.hpp"
#include "rheosim/ldd/case.hpp"
#include "rheosim/ldd/run.hpp"
#include "rheosim/ldd/scenes.hpp"
#include "rheosim/ldd/walls.hpp"

namespace rheosim::ldd {
namespace {

using V = std::vector<double>;

double sdf(const SolidBoundary& b, V x, V* normal = nullptr) {
  V n(3, 0.0);
  const double s = b.signed_distance(x, n);
  if (normal) *normal = n;
  return s;
}

std::filesystem::path temp_file(const std::string& name) { return std::filesystem::temp_directory_path() / name; }

TEST(BoxBoundary, SignedDistanceAndNormalMatchClosedForm) {
  const BoxBoundary box(V{0, 0, 0}, V{1, 2, 3}, true, 0.0);
  V n;
  EXPECT_NEAR(sdf(box, {0.5, 1.0, 1.4}, &n), -0.5, 1e-15);  // inside, nearest face x = 0 or x = 1
  EXPECT_NEAR(std::abs(n[0]), 1.0, 1e-15);
  EXPECT_NEAR(sdf(box, {0.5, 1.9, 1.5}, &n), -0.1, 1e-12);  // inside near y = 2
  EXPECT_EQ(n, (V{0, 1, 0}));
  EXPECT_NEAR(sdf(box, {0.5, 1.0, -0.25}, &n), 0.25, 1e-15);  // below the bottom face
  EXPECT_EQ(n, (V{0, 0, -1}));
  EXPECT_NEAR(sdf(box, {1.3, 2.4, 1.0}, &n), 0.5, 1e-12);  // beyond the edge x = 1, y = 2
  EXPECT_NEAR(n[0], 0.6, 1e-12);
  EXPECT_NEAR(n[1], 0.8, 1e-12);
  EXPECT_NEAR(sdf(box, {-1, -1, 4}, &n), std::sqrt(3.0), 1e-12);  // beyond a corner
  // As a Boundary: fluid inside, wall layer 0.05 beyond the faces; normals into the fluid.
  const BoxBoundary container(V{0, 0, 0}, V{1, 2, 3}, true, 0.05);
  double d = 0;
  V normal(3);
  ASSERT_TRUE(container.distance(V{0.5, 1.0, 0.1}, 0.0, d, normal));
  EXPECT_NEAR(d, 0.15, 1e-12);
  EXPECT_EQ(normal, (V{0, 0, 1}));
  const BoxBoundary obstacle(V{0, 0, 0}, V{1, 2, 3}, false, 0.05);
  ASSERT_TRUE(obstacle.distance(V{0.5, 1.0, 3.2}, 0.0, d, normal));
  EXPECT_NEAR(d, 0.25, 1e-12);
  EXPECT_EQ(normal, (V{0, 0, 1}));
}

TEST(BoxBoundary, TwoDimensionalRectangle) {
  const BoxBoundary box(V{0, 0}, V{2, 1}, true, 0.0);
  V n(2);
  EXPECT_NEAR(box.signed_distance(V{0.3, 0.5}, n), -0.3, 1e-15);
  EXPECT_EQ(n, (V{-1, 0}));
  EXPECT_NEAR(box.signed_distance(V{3, 2}, n), std::sqrt(2.0), 1e-15);
}

TEST(CylinderBoundary, SignedDistanceAndNormalMatchClosedForm) {
  const CylinderBoundary cyl({0, 0, 1}, {0, 0, 2}, 0.5, 2.0, true, 0.0);  // axis length is normalised
  V n;
  EXPECT_NEAR(sdf(cyl, {0.3, 0.0, 2.0}, &n), -0.2, 1e-14);  // inside, nearest the mantle
  EXPECT_NEAR(n[0], 1.0, 1e-14);
  EXPECT_NEAR(sdf(cyl, {0.0, 0.1, 1.05}, &n), -0.05, 1e-14);  // inside, nearest the bottom cap
  EXPECT_NEAR(n[2], -1.0, 1e-14);
  EXPECT_NEAR(sdf(cyl, {0.6, 0.8, 2.0}, &n), 0.5, 1e-14);  // outside the mantle at ρ = 1
  EXPECT_NEAR(n[0], 0.6, 1e-14);
  EXPECT_NEAR(n[1], 0.8, 1e-14);
  EXPECT_NEAR(sdf(cyl, {0.0, 0.0, 3.5}, &n), 0.5, 1e-14);  // above the top cap
  EXPECT_NEAR(n[2], 1.0, 1e-14);
  EXPECT_NEAR(sdf(cyl, {0.8, 0.0, 3.4}, &n), 0.5, 1e-14);  // beyond the top rim: (0.3, 0.4) off it
  EXPECT_NEAR(n[0], 0.6, 1e-14);
  EXPECT_NEAR(n[2], 0.8, 1e-14);
  // A tilted cylinder: along x from the origin.
  const CylinderBoundary tilted({0, 0, 0}, {1, 0, 0}, 1.0, 4.0, false, 0.0);
  EXPECT_NEAR(sdf(tilted, {2.0, 0.0, 1.5}, &n), 0.5, 1e-14);
  EXPECT_NEAR(n[2], 1.0, 1e-14);
  EXPECT_NEAR(sdf(tilted, {-0.25, 0.0, 0.0}, &n), 0.25, 1e-14);
  EXPECT_NEAR(n[0], -1.0, 1e-14);
}

// An STL box written as ASCII and as binary (coordinates exact in float) reads back into a
// closed mesh whose signed distance equals the analytic box's at random points.
TEST(StlBoundary, BoxMeshGivesTheAnalyticBoxDistances) {
  const BoxBoundary box(V{-0.25, 0, 0.5}, V{0.75, 0.5, 1.0}, true, 0.0);
  const TriangleMesh mesh = box_mesh({-0.25, 0, 0.5}, {0.75, 0.5, 1.0});
  EXPECT_NEAR(mesh.volume(), 0.25, 1e-15);
  const auto ascii = temp_file("rheosim_box_ascii.stl"), binary = temp_file("rheosim_box_binary.stl");
  write_stl_ascii(ascii, mesh);
  write_stl_binary(binary, mesh);
  for (const auto& file : {ascii, binary}) {
    const TriangleMesh read = read_stl(file);
    EXPECT_EQ(read.vertices.size(), 8U) << file;  // welded
    EXPECT_EQ(read.triangles.size(), 12U) << file;
    const StlBoundary stl(read, true, 0.0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.5);
    for (int q = 0; q < 500; ++q) {
      const V x{u(rng), u(rng), u(rng)};
      V n_box, n_stl;
      const double expected = sdf(box, x, &n_box), got = sdf(stl, x, &n_stl);
      ASSERT_NEAR(got, expected, 1e-12) << file << " at " << x[0] << ", " << x[1] << ", " << x[2];
      if (expected > 1e-9 || expected < -1e-9) {  // the normal is unique off the surface (except medial points)
        double dot = 0;
        for (int d = 0; d < 3; ++d) dot += n_box[d] * n_stl[d];
        if (expected > 0) {
          EXPECT_NEAR(dot, 1.0, 1e-9);
        }
      }
    }
  }
  // A mesh read with the opposite winding is reoriented (volume > 0).
  TriangleMesh flipped = mesh;
  for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
  write_stl_ascii(ascii, flipped);
  EXPECT_NEAR(read_stl(ascii).volume(), 0.25, 1e-15);
  std::filesystem::remove(ascii);
  std::filesystem::remove(binary);
}

// A 256-sided STL cylinder against the analytic one: distances agree to the polygon's sagitta
// R(1 − cos(π/256)) and the sign (inside/outside) agrees away from the surface.
TEST(StlBoundary, CylinderMeshMatchesTheAnalyticCylinder) {
  const double radius = 0.1, height = 0.2;
  const CylinderBoundary cyl({0, 0, 0}, {0, 0, 1}, radius, height, true, 0.0);
  const auto file = temp_file("rheosim_cylinder.stl");
  write_stl_binary(file, cylinder_mesh({0, 0, 0}, radius, height, 256));
  const StlBoundary stl(read_stl(file), true, 0.0);
  std::filesystem::remove(file);
  const double sagitta = radius * (1 - std::cos(std::numbers::pi / 256));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.2, 0.2), w(-0.1, 0.3);
  for (int q = 0; q < 400; ++q) {
    const V x{u(rng), u(rng), w(rng)};
    const double expected = sdf(cyl, x), got = sdf(stl, x);
    ASSERT_NEAR(got, expected, sagitta + 1e-6) << x[0] << ", " << x[1] << ", " << x[2];
    if (std::abs(expected) > 2 * sagitta) {
      EXPECT_EQ(got > 0, expected > 0);
    }
  }
}

TEST(StlReader, RejectsOpenMeshesAndNamesTheBadLine) {
  TriangleMesh open = box_mesh({0, 0, 0}, {1, 1, 1});
  open.triangles.pop_back();
  const auto file = temp_file("rheosim_open.stl");
  write_stl_ascii(file, open);
  try {
    (void)read_stl(file);
    ADD_FAILURE() << "an open mesh was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
  }
  {
    std::ofstream out(file);
    out << "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 zero\n";
  }
  try {
    (void)read_stl(file);
    ADD_FAILURE() << "a malformed vertex was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("line 5"), std::string::npos) << e.what();
  }
  std::filesystem::remove(file);
}

// Wall nodes lie on the wall layer (Boundary distance 0), about Δ apart; their normals point into
// the fluid.
TEST(WallNodes, LieOnTheWallLayer) {
  const double dx = 0.01;
  const BoxBoundary box(V{0, 0, 0}, V{0.1, 0.05, 0.08}, true, 0.5 * dx);
  const CylinderBoundary cyl({0, 0, 0}, {0, 0, 1}, 0.05, 0.1, true, 0.5 * dx);
  const auto file = temp_file("rheosim_nodes.stl");
  write_stl_ascii(file, box_mesh({0, 0, 0}, {0.1, 0.05, 0.08}));
  const StlBoundary stl(read_stl(file), true, 0.5 * dx);
  std::filesystem::remove(file);
  for (const SolidBoundary* b : std::initializer_list<const SolidBoundary*>{&box, &cyl, &stl}) {
    const auto nodes = b->wall_nodes(dx);
    ASSERT_GT(nodes.size(), 50U);
    for (const WallNode& node : nodes) {
      double d = 0;
      V normal(3);
      ASSERT_TRUE(b->distance(node.x, 0.0, d, normal));
      // On the layer. Corner/rim nodes and STL face samples near edges sit off the (rounded)
      // offset surface by up to (√2 − 1)Δ/2 and Δ/2.
      const bool exact = !node.corner && dynamic_cast<const StlBoundary*>(b) == nullptr;
      EXPECT_NEAR(d, 0.0, exact ? 1e-9 : 0.5 * dx);
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += normal[k] * node.normal[k];
      EXPECT_GT(dot, 0.5);
    }
  }
  // The box layer: 10 × 5 × 8 cells, faces at the cell centres of each face plus edges and corners.
  EXPECT_EQ(box.wall_nodes(dx).size(), 2U * (10 * 5 + 10 * 8 + 5 * 8) + 4U * (10 + 5 + 8) + 8U);
}

TEST(WallRegistry, BuildsEveryTypeByNameAndRejectsUnknownOnes) {
  EXPECT_EQ(wall_types(), (std::vector<std::string>{"plane", "box", "cylinder", "stl"}));
  ldd::WallSettings w;
  w.type = "cylinder";
  w.base = {0, 0, 0};
  w.axis = {0, 0, 1};
  w.radius = 0.1;
  w.height = 0.1;
  const V lo{-1, -1, -1}, hi{1, 1, 1};
  const BuiltWall built = make_wall(w, 3, 0.01, lo, hi);
  ASSERT_NE(built.boundary, nullptr);
  EXPECT_GT(built.nodes.size(), 100U);
  w.type = "plane";
  w.point = {0, 0, 0};
  w.normal = {0, 0, 1};
  const BuiltWall plane = make_wall(w, 3, 0.5, lo, hi);
  EXPECT_EQ(plane.nodes.size(), 25U);  // a 5 × 5 lattice at z = −Δ/2 inside [−1, 1]²
  w.type = "sphere";
  EXPECT_THROW((void)make_wall(w, 3, 0.01, lo, hi), std::invalid_argument);
}

std::string slump_case(const std::string& walls) {
  return "kind: ldd\ndimension: 3\nscene:\n  type: slump\n  cone: {height: 0.1, bottom_diameter: 0.08, top_diameter: "
         "0.04}\n"
         "  lift_velocity: 0.5\n  walls:\n" +
         walls +
         "fluid: {density: 1000, rheology: {model: newtonian, viscosity: 10.0}}\ngravity: [0, 0, -9.81]\n"
         "resolution: {spacing: 0.01}\ntime: {step: 2.0e-3, end: 0.6}\nsolver: {pbd_sweeps: 6, moment_rcond: 0.01}\n";
}

// Bad wall entries fail at parse time naming the file, line, key and the valid range.
TEST(WallCaseFile, BadEntriesNameLineKeyAndRange) {
  const auto message = [](const std::string& walls) {
    try {
      (void)ldd::parse_case(slump_case(walls), "walls.yaml");
    } catch (const core::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string radius = message("    - {type: cylinder, base: [0, 0, 0], radius: -0.1, height: 0.1}\n");
  EXPECT_NE(radius.find("walls.yaml:8"), std::string::npos) << radius;
  EXPECT_NE(radius.find("radius"), std::string::npos) << radius;
  EXPECT_NE(radius.find("> 0"), std::string::npos) << radius;
  const std::string type = message("    - {type: cylindr, base: [0, 0, 0], radius: 0.1, height: 0.1}\n");
  EXPECT_NE(type.find("cylinder"), std::string::npos) << type;  // the valid choices are listed
  const std::string box = message("    - {type: box, lower: [0, 0, 0], upper: [1, -1, 1]}\n");
  EXPECT_NE(box.find("upper"), std::string::npos) << box;
  const std::string stl = message("    - {type: stl, file: no_such_file.stl}\n");
  EXPECT_NE(stl.find("no_such_file.stl"), std::string::npos) << stl;
  EXPECT_EQ(message("    - {type: cylinder, base: [0, 0, 0], radius: 0.07, height: 0.15}\n"), "no error");
}

// `rheosim validate` shows the walls and the free-surface solver settings it read.
TEST(WallCaseFile, DescribeListsTheWalls) {
  const auto c = ldd::parse_case(slump_case("    - {type: cylinder, base: [0, 0, 0], radius: 0.07, height: 0.15}\n"
                                            "    - {type: box, lower: [-1, -1, 0], upper: [1, 1, 1]}\n"),
                                 "walls.yaml");
  const std::string text = ldd::describe(c);
  EXPECT_NE(text.find("wall: cylinder base [0, 0, 0] m"), std::string::npos) << text;
  EXPECT_NE(text.find("radius 0.07 m, height 0.15 m, fluid inside"), std::string::npos) << text;
  EXPECT_NE(text.find("wall: box"), std::string::npos) << text;
  EXPECT_NE(text.find("6 PBD sweeps per step (velocity: taylor, surface nodes: full shift), moment-matrix rcond 0.01"),
            std::string::npos)
      << text;
}

// The case file cases/ldd_slump_cylinder.yaml: the liquid spreads to the container wall and no
// fluid node crosses it (all stay ≥ Δ/2 − tolerance inside the wall layer, i.e. within the
// physical radius); volume kept within 1 %. The same container as an STL cylinder behaves alike.
void run_in_container(const ldd::Case& c, double radius) {
  omp_set_num_threads(1);  // seconds on a loaded 2-core machine; results are per-thread-count anyway
  const auto& l = c.settings;
  FreeSurfaceScene scene = slump_scene(std::get<ldd::SlumpScene>(l.scene), l.spacing, l.walls);
  FreeSurfaceSolver solver(free_surface_params(l), std::move(scene.boundaries), std::move(scene.cloud));
  const double volume0 = solver.fluid_volume();
  double reach = 0;
  const auto steps = static_cast<int>(std::lround(l.end_time / l.time_step));
  for (int k = 0; k < steps; ++k) {
    ASSERT_NO_THROW(solver.step()) << "step " << k;
    for (std::size_t i = 0; i < solver.node_count(); ++i) {
      if (!solver.is_fluid(i)) continue;
      const double r = std::hypot(solver.positions()[3 * i], solver.positions()[3 * i + 1]);
      reach = std::max(reach, r);
      ASSERT_LE(r, radius + 1e-3) << "fluid node " << i << " left the container at step " << k;
    }
  }
  EXPECT_GT(reach, radius - l.spacing);  // it did reach the wall (else the test proves nothing)
  EXPECT_LT(std::abs(solver.fluid_volume() / volume0 - 1), 0.01);
}

TEST(WallCaseFile, SlumpInACylindricalContainerStaysInside) {
  const ldd::Case c = ldd::load_case(std::string(RHEOSIM_SOURCE_DIR) + "/cases/ldd_slump_cylinder.yaml");
  run_in_container(c, 0.07);
}

TEST(WallCaseFile, SlumpInAnStlContainerStaysInside) {
  const auto file = temp_file("rheosim_container.stl");
  write_stl_binary(file, cylinder_mesh({0, 0, 0}, 0.07, 0.15, 32));
  const ldd::Case c = ldd::parse_case(slump_case("    - {type: stl, file: " + file.string() + "}\n"), "stl.yaml");
  run_in_container(c, 0.07);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace rheosim::ldd
