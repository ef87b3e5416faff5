// Becker & Max 1993, eq. 4 (Blinn 1978): the bump-mapped normal.
#pragma once

#include "meso/core/math.h"

namespace meso {

// The normal of the displaced surface P + h N to first order in h, for any P_u, P_v (stretched,
// non-orthogonal) and B_u = dh/du, B_v = dh/dv in world units per unit of u and v:
//   N' = normalize(P_u x P_v + B_u (N x P_v) - B_v (N x P_u)) = normalize(P'_u x P'_v),
//   P'_u = P_u + B_u N,  P'_v = P_v + B_v N,
// with N of unit length in the cross terms (eq. 4 as printed has the unnormalized P_u x P_v
// there, which is right only when |P_u x P_v| = 1). N is the direction displacement follows
// (normally normalize(P_u x P_v)); the result faces the same side as N. Never NaN: a degenerate
// frame (P_u x P_v = 0, zero N) or non-finite input gives N (or +z if N is unusable); huge B gives
// the limiting, tangential normal.
Vec3 blinnNormal(const Vec3& Pu, const Vec3& Pv, const Vec3& N, float Bu, float Bv);
// Same with N = normalize(P_u x P_v).
Vec3 blinnNormal(const Vec3& Pu, const Vec3& Pv, float Bu, float Bv);

}  // namespace meso
