// The shading of one relief level by each renderer of DESIGN.md section 2 (Becker & Max 1993,
// sections 2 to 4). Shared by the image renderer and by `meso consistency`, so the consistency
// numbers measure the code that renders images.
#pragma once

#include "meso/appearance/brdf_table.h"
#include "meso/appearance/redistribution.h"
#include "meso/core/math.h"
#include "meso/render/tile_map.h"
#include "meso/scene/scene.h"

#include <span>

namespace meso {

// The view-aligned frame at a shading point: N the level's macro normal, T the direction of V
// projected onto the tangent plane (phi_V = 0), B = N x T. The tables' phi axis is phi_N - phi_V,
// so expressing normals in this frame is all the azimuth bookkeeping they need.
struct ViewFrame {
  Vec3 N{0.0f, 0.0f, 1.0f};
  Vec3 T{1.0f, 0.0f, 0.0f};
  Vec3 B{0.0f, 1.0f, 0.0f};
  float thetaV = 0.0f;  // angle between V and N, clamped to [0, pi/2]
};

// Builds the frame; at normal incidence (V parallel to N) T is any unit tangent, here `tangentHint`
// made orthogonal to N (or an arbitrary perpendicular if that is degenerate too).
ViewFrame makeViewFrame(const Vec3& N, const Vec3& V, const Vec3& tangentHint);

inline Vec3 toFrame(const ViewFrame& f, const Vec3& w) {
  return {glm::dot(w, f.T), glm::dot(w, f.B), glm::dot(w, f.N)};
}
inline Vec3 fromFrame(const ViewFrame& f, const Vec3& v) {
  return v.x * f.T + v.y * f.B + v.z * f.N;
}

// Redistribution bump mapping (section 3) with partial displacement (section 4.1): the bump normal
// nBump (world, unit) mapped by n' = R_thetaV(R_thetaW^-1(n)); disp = 0 is plain redistribution,
// disp >= 1 returns nBump exactly.
Vec3 redistributeNormal(const Redistribution& r, const ViewFrame& f, float disp, const Vec3& nBump);

// The BRDF renderer: ka + sum over lights of radiance * (kd BRDF_diff + ks BRDF_spec) at
// (theta_V, theta_L, phi_{V-L}). Lights below the macro horizon add nothing. phi_{V-L} follows the
// paper's eq. (2) when the level's tangents are given: the angle between V_n = [V.P_u, V.P_v] and
// L_n = [L.P_u, L.P_v], so a stretched or warped parameterization stretches the table's azimuths
// with it (anisotropic highlights where the relief is stretched); without them (or when V or L is
// along N) it is the angle between the projections of V and L on the tangent plane.
Vec3 shadeBrdf(const Reflectance& material, std::span<const Light> lights, const Vec3& P,
               const ViewFrame& f, const BrdfTable& brdf, const Vec3* Pu = nullptr,
               const Vec3* Pv = nullptr);

// Redistribution on a surface of any metric (docs/metric.md): the bump normal and V go to the
// tile of the metric class by `m` (M^T n and M^-1 V), are redistributed there, and the result
// comes back by M^-T. Exact in distribution for any P_u, P_v when the tile relief is isotropic.
Vec3 redistributeNormal(const Redistribution& r, const TileMap& m, const Vec3& V, float disp,
                        const Vec3& nBump);

// The view-aligned frame of tile coordinates (macro normal +z) for a tile-space direction v (not
// necessarily unit; zero or non-finite: straight up).
ViewFrame tileViewFrame(const Vec3& v);

// phi_{V-L} of eq. (2) in [0, pi], or a negative value when V_n or L_n vanishes.
float azimuthEq2(const Vec3& V, const Vec3& L, const Vec3& Pu, const Vec3& Pv);

}  // namespace meso
