// Closed, outward-facing solids for the procedural maps. Every call adds one solid whose vertices
// are shared between its triangles, so each edge is used by exactly two triangles in opposite
// directions, and whose triangles are counter-clockwise seen from outside. Point-in-solid tests
// rely on this: a ray from a point inside a solid first hits a back face.
//
// Solids may touch or overlap each other. They should not share vertex positions exactly: a
// loader that welds identical vertices would then see edges with four triangles (non-manifold).
#pragma once

#include <polyloc/map/mesh.hpp>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace polyloc::mapgen {

// Triangulates a simple polygon (no self-intersections, no repeated points) by ear clipping.
// Indices refer to the input; triangles are counter-clockwise whatever the input orientation.
std::vector<Triangle> triangulatePolygon(const std::vector<Eigen::Vector2f>& polygon);

// Signed volume enclosed by the triangles: positive when closed and facing outward.
double signedVolume(const Mesh& mesh);

class MeshBuilder {
 public:
  explicit MeshBuilder(Mesh& mesh) : mesh_(mesh) {}
  Mesh& mesh() { return mesh_; }

  // Place the following solids: local (x, y) is rotated by yaw about z, then shifted by origin,
  // z is raised by z. Frames compose with the current one, so furniture can be placed by a
  // frame and built from its own parts in local coordinates.
  void pushFrame(const Eigen::Vector2f& origin, float yaw = 0.f, float z = 0.f);
  void popFrame();

  // Axis-aligned (in the current frame) box between corners lo and hi.
  void box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, const std::string& label);
  // Box of size (x, y) centred at centre, turned by yaw about z, between heights z0 and z1.
  void orientedBox(const Eigen::Vector2f& centre, const Eigen::Vector2f& size, float yaw, float z0,
                   float z1, const std::string& label);
  // Footprint polygon (simple, either orientation) extruded from z0 to z1.
  void prism(const std::vector<Eigen::Vector2f>& footprint, float z0, float z1,
             const std::string& label);
  // Vertical cylinder approximated by a regular prism with `segments` sides.
  void cylinder(const Eigen::Vector2f& centre, float radius, float z0, float z1, int segments,
                const std::string& label);
  // Wedge over [lo.x, hi.x] x [lo.y, hi.y] rising along +x: the top goes from z_low at lo.x to
  // z_high at hi.x, the bottom is flat at z_base (z_base < z_low gives a sloped slab).
  void ramp(const Eigen::Vector2f& lo, const Eigen::Vector2f& hi, float z_base, float z_low,
            float z_high, const std::string& label);
  // Staircase along +x from x0, across [y0, y1]: step k = 1..steps has its tread at
  // z_start + k * rise over [x0 + (k-1) tread, x0 + k tread] (rise < 0 goes down). The steps form
  // one solid that reaches down to z_base, so no two step boxes share an edge.
  void stairs(float x0, float y0, float y1, float z_start, int steps, float rise, float tread,
              float z_base, const std::string& label);
  // Rectangular slab [lo, hi] between z0 and z1 with a rectangular hole strictly inside it.
  void slabWithHole(const Eigen::Vector2f& lo, const Eigen::Vector2f& hi,
                    const Eigen::Vector2f& hole_lo, const Eigen::Vector2f& hole_hi, float z0,
                    float z1, const std::string& label);
  // General extrusion: polygon (u, v) in the plane origin + u e1 + v e2, swept along e1 x e2 from
  // w0 to w1 (w0 < w1). e1, e2 orthonormal, in the current frame.
  void extrude(const std::vector<Eigen::Vector2f>& polygon, const Eigen::Vector3f& origin,
               const Eigen::Vector3f& e1, const Eigen::Vector3f& e2, float w0, float w1,
               const std::string& label);

 private:
  struct Frame {
    Eigen::Vector2f origin{0.f, 0.f};
    float c = 1.f, s = 0.f, z = 0.f;
    Eigen::Vector3f apply(const Eigen::Vector3f& p) const;
  };
  // Appends one solid in the current frame; throws std::logic_error if it is not outward.
  void addSolid(const std::vector<Eigen::Vector3f>& vertices, const std::vector<Triangle>& tris,
                const std::string& label);

  Mesh& mesh_;
  std::vector<Frame> frames_{Frame{}};
};

}  // namespace polyloc::mapgen
