// View-dependent, displaced, crack-free micropolygons of a limit surface: per-edge Bfr rates from a
// screen metric, vertices displaced along the limit normal (Becker & Max 1993 section 2.3;
// shared/DESIGN.md section 5).
#pragma once

#include "meso/core/math.h"
#include "meso/geometry/dicing_metric.h"
#include "meso/geometry/limit_surface.h"
#include "meso/geometry/ray_scene.h"
#include "meso/geometry/screen_metric.h"
#include "meso/geometry/tessellation.h"

#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace meso {

// What dicing holds per control face of a displaced object besides its micropolygons, at its
// peak: edge measures, split plans, the tessellator's topology and the one-cell grid of a face out
// of view. Measured with heaptrack on a ground of 409 600 unit quads at 1280x720 (about 550
// bytes); --memory-limit takes it off the micropolygons' share (render_context.cpp).
inline constexpr double kDicingBytesPerFace = 560.0;
// The same for an object tessellated by view with nothing displaced (bump and the other renderers
// that displace nothing, render.tessellation_rate 0): no split plans, no displacement bounds, and
// the measures are released before the mesh is made. Measured with heaptrack on a ground of
// 409 600 Catmull-Clark faces with hills in its shape under bump at 1280x720 (the heap rose by
// 50.5 MB while the rates were chosen, 61 MB at most: 149 bytes a face).
inline constexpr double kViewTessellationBytesPerFace = 150.0;

struct DicingSettings {
  float dicingRate = 1.0f;  // longest micropolygon edge in pixels where a face needs dicing
  DicingMetric metric = DicingMetric::Isotropic;
  int maxEdgeRate = 256;  // most segments on one mesh edge
  // Where no adjacent face needs dicing, edges are split until the limit surface deviates from
  // the chords by about this many pixels. Chords cut inside a convex silhouette, so this is a bias
  // in what an object covers: a Catmull-Clark cube about 57 px across covered 3.4% less at 0.5 px,
  // 0.45% at 0.05 and 0.04% at 0.01 (AdaptiveTessellation.CoarseSilhouettesCover...), and a far
  // torus drawn by the hybrid's tables alone was 1.7% darker than with any one renderer at 0.5 px.
  // Triangles grow as 1 / tolerance, on curved undiced faces only: a few thousand a frame.
  float coarseTolerance = 0.01f;
  // Cap on triangles: about 160 bytes each with the Embree scene (tools/bench_tessellation), so the
  // default keeps a frame's geometry within about half of a 24 GiB machine.
  size_t maxMicropolygons = 80'000'000;
  // Split the interior of diced quad faces that are partly out of view or whose pixel density
  // varies by more than 2x, each sub-quad at its own rate (mesh edges keep theirs, so no cracks).
  bool splitFaces = true;
  // Leave the triangles of the Embree grids out of the mesh's per-triangle arrays (indices, faces,
  // patch coordinates: 40 bytes a micropolygon); the grids alone hold them and know their face and
  // st (TriangleGrid::kNotInMesh). The renderer's setting; code that walks the mesh's triangles
  // leaves it off.
  bool gridsOnly = false;
  // Anisotropic caps at grazing views: the share of a diced face's texel cap that edges running
  // across the view keep, 1 - (1 - acrossViewCap) (1 - c^2) sin^2(theta_V) (c: the cosine between
  // the edge and the view's direction in the tangent plane). Seen head-on, or along the view, the
  // whole cap. Below 1 only for the hybrid (render.across_view_cap, 0.5: 4 edges per shortest
  // wavelength across where the cap is 8; docs/performance.md): along the view the relief's
  // samples decide what the grazing rays hit; across it the shading normals, evaluated from the
  // relief at each hit, carry the detail.
  float acrossViewCap = 1.0f;
  // Faces out of view serve only the frame's shadow rays. With shadowCasters set, a face out of
  // view is kept (as one-cell grids) only where its box, grown by the displacement bound, may
  // block a shadow ray from a point of the scene's box that a ray from the eye may reach, that is
  // where the box swept towards the frame's points (away from each light, within the scene's box)
  // meets the view (mayShadowView); the other faces out of view get no geometry. Unset: every face
  // is kept (an environment light, a light with a radius, or a caller that traces other rays).
  struct ShadowCasters {
    Vec3 sceneLo{0.0f}, sceneHi{0.0f};  // every object's box, grown by its displacement bound
    std::vector<Vec3> directions;       // towards each directional light (unit)
    std::vector<Vec3> points;           // each point light's position (radius 0)
  };
  std::optional<ShadowCasters> shadowCasters;
};

// Whether a box (a face's, grown by its displacement bound) out of view may block a shadow ray that
// starts at a point of the scene's box in view: for each light, the box swept towards the points
// it may shadow (along the light's rays, within the scene's box) meets the view. Conservative:
// true whenever it cannot tell.
bool mayShadowView(const Vec3& lo, const Vec3& hi, const ScreenMetric& screen,
                   const DicingSettings::ShadowCasters& casters);

// What the caller knows per base face (vectors indexed by face; empty means the default for all).
struct FaceDicing {
  // Nonzero: some relief level may be displaced on this face (its T can exceed e3), so it is diced
  // at DicingSettings::dicingRate. Default: every face.
  std::vector<char> needsDicing;
  // The largest useful edge rate of the face (e.g. from its finest displaced level's texel
  // spacing); 0 = no cap. Default: no caps.
  std::vector<int> texelCap;
  // The least edge rate of a face in view that is diced (e.g. so that displaced micropolygons
  // resolve the relief where it is smaller than a pixel); 0 = none, at most texelCap. Default:
  // none.
  std::vector<int> texelFloor;
  // Where relief is raised only near the eye (the hybrid's T falls with distance): a part of a
  // diced face whose surface, grown by the displacement bound, lies wholly farther than this from
  // the eye (world units) is not displaced, so it gets only the coarse rate. Split faces dice such
  // parts so (as DiagSplit splits where the rate changes); a face's mesh edges are diced when some
  // of the edge is near enough. Infinity: the whole face. Default: infinity for all.
  std::vector<float> raiseDistance;

  // Whether relief may be raised somewhere in the box [lo - grow, hi + grow] of face f: its
  // distance from the eye is below raiseDistance[f] (true when unsure: NaN distances).
  bool raisesBox(int f, Vec3 eye, Vec3 lo, Vec3 hi, float grow) const {
    if (raiseDistance.empty()) return true;
    return !(boxDistance(eye, lo - Vec3(grow), hi + Vec3(grow)) >=
             raiseDistance[static_cast<size_t>(f)]);
  }
};

// Whether base face `face` may be seen in the frame: the box of its patch points, grown by `grow`
// (the displacement bound), is in view. The limit patch lies in the convex hull of its patch points
// (B-spline and Gregory bases are non-negative and sum to one), so the test is conservative.
// Adaptive tessellation culls the faces that fail it with the bound of their VertexDisplacement,
// and reads no FaceDicing entry of theirs.
bool faceInView(const LimitSurface& surface, const ScreenMetric& screen, int face, float grow);

// How tessellated vertices move off the limit surface; the caller implements it (meso's renderer:
// sum_i disp_i * h_i(u, v) * N_i). Called once per output vertex, concurrently from several
// threads, so offset() must be thread-safe and should not allocate.
class VertexDisplacement {
 public:
  virtual ~VertexDisplacement() = default;
  // Offset of the limit point sp, which lies on base face `face` at patch coordinates st.
  virtual Vec3 offset(int face, Vec2 st, const SurfacePoint& sp) const = 0;
  // An upper bound of |offset| over the whole surface (world units): it grows the boxes of the
  // view test, so a face whose relief reaches into the view is not culled.
  virtual float bound() const = 0;
};

struct AdaptiveTessellationStats {
  size_t micropolygons = 0;  // triangles
  // Triangles none of whose vertices is in view (ScreenMetric::pointInView): outside the frustum,
  // they only cost (faces straddle its border, and faces just outside it are diced because their
  // relief might rise into view). A triangle wider than the view can be counted and yet be seen.
  size_t offScreenMicropolygons = 0;
  size_t vertices = 0;
  int facesDiced = 0;   // in view and needing dicing
  int facesCulled = 0;  // outside the view: their edges not shared with a visible face get rate 1
  // Diced quad faces whose interior was split into sub-quads, each with its own rate, because
  // part of the face is out of view or its pixel density varies by more than 2x across it.
  int facesSplit = 0;
  int minEdgeRate = 0;
  int maxEdgeRate = 0;
  // Where the cap (DicingSettings::maxMicropolygons) coarsened the dicing: every edge and sub-quad
  // of a face that reaches nearer than coarsenedBeyond (world units from the eye; infinity: not
  // capped) is diced as asked, and geometry at distance d beyond it by d / coarsenedBeyond.
  float coarsenedBeyond = std::numeric_limits<float>::infinity();
  // The largest factor the cap coarsened a rate by (1: not capped): the farthest geometry's; the
  // dicing rate there is DicingSettings::dicingRate times this.
  float coarsening = 1.0f;
  double rateSeconds = 0.0;      // edge rates, culling, pattern counts and the cap
  double evaluateSeconds = 0.0;  // connectivity, limit evaluation and displacement
};

struct AdaptiveTessellation {
  TessellatedMesh mesh;
  // The interior of every quad face (of every sub-quad of a split face) as a regular grid block
  // of `mesh` (points row by row, cells split as Embree splits grid cells), for
  // RayScene::addMesh(mesh, grids): most micropolygons then cost Embree grid memory instead of
  // triangle memory.
  std::vector<TriangleGrid> grids;
  // Segments on each mesh edge, in OpenSubdiv's base-level edge numbering; both faces of an edge
  // use its rate, which is why the mesh has no cracks.
  std::vector<int> edgeRates;
  AdaptiveTessellationStats stats;
  std::string warning;  // non-empty when the micropolygon cap coarsened the tessellation
};

// Tessellates every face that has a limit surface. Per mesh edge: where an adjacent face is in view
// and needs dicing, rate = ceil(pixel length of the limit edge / dicingRate), clamped to
// [1, min(maxEdgeRate, the largest texel cap of those faces)]: the length is the projected one
// or, by default (DicingMetric::Isotropic), the edge's footprint length and at least its world
// length times the largest pixelDensity in view on those faces; where an adjacent face is in view,
// at least the coarse rate that follows the limit surface to coarseTolerance pixels; elsewhere 1.
// A face is in view when the box of its limit patch, grown by displacement->bound(), is. With
// DicingSettings::splitFaces, a diced quad face partly out of view, partly beyond its
// FaceDicing::raiseDistance or whose pixel density varies by more than 2x across it has its
// interior split into up to 16 x 16 sub-quads, each diced at the rate of its own part (the coarse
// rate where it needs no dicing) between the unchanged mesh edges (face_split.h in src/geometry).
// If the triangles would exceed maxMicropolygons, the farthest geometry is coarsened first: each
// mesh edge and sub-quad by max(1, d / D), d the distance from the eye to the nearest point of
// the faces it belongs to (an edge: of every face in view it bounds, so both faces agree), with
// about the largest D for which the triangles fit; every face that reaches nearer than D keeps
// the rates asked, and `warning` and the stats say D and the worst factor. displacement may be null
// (the undisplaced limit surface). Throws meso::Error on invalid settings or per-face vectors of
// the wrong size. The output is the same, bit for bit, whatever the number of threads.
AdaptiveTessellation tessellateAdaptive(const LimitSurface& surface, const ScreenMetric& screen,
                                        const DicingSettings& settings, const FaceDicing& faces,
                                        const VertexDisplacement* displacement);

// One surface of a frame, for the form of tessellateAdaptive that dices several under one cap.
struct AdaptiveSurface {
  const LimitSurface* surface = nullptr;
  FaceDicing faces;
  const VertexDisplacement* displacement = nullptr;  // may be null
};

// The surfaces of one frame, each as tessellateAdaptive above, under one cap: maxMicropolygons
// bounds their triangles together, and one D serves all of them, so the frame's farthest geometry
// is coarsened first whichever surface it belongs to. Each result's stats and warning give the
// shared D (coarsenedBeyond) and that surface's worst factor.
std::vector<AdaptiveTessellation> tessellateAdaptive(std::span<const AdaptiveSurface> surfaces,
                                                     const ScreenMetric& screen,
                                                     const DicingSettings& settings);

}  // namespace meso
