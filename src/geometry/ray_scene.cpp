// An Embree 3 scene of triangles and grids (shared/DESIGN.md section 5: the tessellated surface is
// traced by Embree) with robust, watertight closest-hit queries.
#include "meso/geometry/ray_scene.h"

#include "meso/core/error.h"
#include "meso/core/huge_pages.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace meso {
namespace {

// A 2 x 2 grid of the triangles outside the grid blocks: one mesh triangle, or two that share
// the cell's diagonal (pairCells). The lower one's corners `lowerTurn`, `lowerTurn` + 1 and
// `lowerTurn` + 2 (mod 3) are the cell's p00, p10 and p01; the upper one's `upperTurn`, ... are
// its p11, p01 and p10 (Embree's split of a cell, TriangleGrid).
struct Cell {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  uint32_t lower = 0, upper = kNone;  // mesh triangles; kNone: the upper half has no area
  uint8_t lowerTurn = 0, upperTurn = 0;
};

}  // namespace

struct RayScene::Impl {
  // What an Embree geometry holds: all triangles of a mesh, or its grid blocks followed by its
  // other triangles in cells.
  struct Part {
    int mesh = -1;
    bool isGrid = false;
    std::vector<TriangleGrid> grids;  // primitives 0 .. grids.size() - 1 of a grid geometry
    std::vector<Cell> cells;          // the later primitives
    std::vector<Vec3> points;         // Embree's vertex buffer, if the scene holds it (takeMesh)
  };

  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  int numMeshes = 0;
  std::vector<Part> parts;  // by Embree geometry ID
  std::mutex errorMutex;
  std::string firstError;  // the first Embree error not yet reported, empty if none
  std::atomic<long long> bytes{0}, peakBytes{0};

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  // Embree reports API errors through this callback rather than return codes.
  static void onError(void* self, RTCError code, const char* message) {
    auto* impl = static_cast<Impl*>(self);
    std::lock_guard<std::mutex> lock(impl->errorMutex);
    if (impl->firstError.empty())
      impl->firstError = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
                         (message ? message : "(no message)");
  }

  // Embree reports every allocation (bytes > 0) and release (bytes < 0) of the device here;
  // returning true lets it proceed.
  static bool onMemory(void* self, ssize_t bytes, bool /*post*/) {
    auto* impl = static_cast<Impl*>(self);
    const long long now = impl->bytes.fetch_add(bytes) + bytes;
    long long peak = impl->peakBytes.load();
    while (now > peak && !impl->peakBytes.compare_exchange_weak(peak, now)) {
    }
    return true;
  }

  // Our hit for Embree's answer; false on a miss.
  bool hitOf(const RTCRayHit& rh, RayHit& hit) const;

  void attach(RTCGeometry geometry, Part part) {
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);  // the scene holds the reference now
    throwIfError();
    if (id >= parts.size()) parts.resize(id + 1);
    parts[id] = std::move(part);
  }

  void throwIfError() {
    std::lock_guard<std::mutex> lock(errorMutex);
    if (firstError.empty()) return;
    std::string message;
    message.swap(firstError);
    throw Error(message);
  }
};

namespace {

// memcpy in 2 MiB pieces on every core: the fresh buffer's pages are zeroed by the kernel at their
// first write, which on one core took a tenth of a second for the vertices of 6 M micropolygons.
void copyInParallel(void* to, const void* from, std::size_t bytes) {
  constexpr std::size_t kPiece = kHugePageBytes;
  tbb::parallel_for(std::size_t(0), (bytes + kPiece - 1) / kPiece, [&](std::size_t k) {
    const std::size_t at = k * kPiece;
    std::memcpy(static_cast<char*>(to) + at, static_cast<const char*>(from) + at,
                std::min(kPiece, bytes - at));
  });
}

}  // namespace

RayScene::RayScene() : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device)
    throw Error("Embree device creation failed (error " +
                std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(impl_->device, &Impl::onError, impl_.get());
  rtcSetDeviceMemoryMonitorFunction(impl_->device, &Impl::onMemory, impl_.get());
  impl_->scene = rtcNewScene(impl_->device);
  // ROBUST makes the triangle test watertight: a ray through a shared edge or vertex of two
  // triangles hits one of them, so tessellated closed surfaces never leak.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  // The scene is rebuilt for every frame of a fly-through: MEDIUM builds faster than HIGH at a
  // small cost in ray rate.
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_MEDIUM);
  impl_->throwIfError();
}

RayScene::~RayScene() = default;

int RayScene::addMesh(const TessellatedMesh& mesh) {
  if (mesh.gridOnlyTriangles > 0)
    throw Error("a mesh whose grids hold some of its triangles needs those grids");
  const int index = impl_->numMeshes++;
  const size_t numTriangles = mesh.indices.size() / 3;
  // An empty mesh keeps its index but needs no geometry (Embree rejects empty buffers).
  if (numTriangles == 0) return index;
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree owns these copies (padded as its SIMD loads need), so `mesh` may go away afterwards.
  void* vertices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                           sizeof(Vec3), mesh.positions.size());
  if (vertices) {
    adviseHugePages(vertices, mesh.positions.size() * sizeof(Vec3));  // before the first touch
    copyInParallel(vertices, mesh.positions.data(), mesh.positions.size() * sizeof(Vec3));
  }
  void* indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                          3 * sizeof(uint32_t), numTriangles);
  if (indices) {
    adviseHugePages(indices, numTriangles * 3 * sizeof(uint32_t));
    copyInParallel(indices, mesh.indices.data(), numTriangles * 3 * sizeof(uint32_t));
  }
  impl_->attach(geometry, {.mesh = index, .isGrid = false, .grids = {}, .cells = {}, .points = {}});
  numTriangles_ += numTriangles;
  numPrimitives_ += numTriangles;
  return index;
}

namespace {

// The mesh triangles no grid covers, after checking that the grids fit the mesh and do not overlap
// (grids whose triangles are not stored come last, after the sort, and need only fit the points).
std::vector<uint32_t> trianglesOutsideGrids(const TessellatedMesh& mesh,
                                            std::vector<TriangleGrid>& grids) {
  std::stable_sort(grids.begin(), grids.end(), [](const TriangleGrid& a, const TriangleGrid& b) {
    return a.firstTriangle < b.firstTriangle;
  });
  std::vector<uint32_t> outside;
  size_t next = 0;  // first triangle not yet classified
  size_t gridOnly = 0;
  for (const TriangleGrid& g : grids) {
    const size_t cells = size_t(g.width - 1) * size_t(g.height - 1);
    const bool stored = g.firstTriangle != TriangleGrid::kNotInMesh;
    if (g.width < 2 || g.height < 2 || g.width > 32767 || g.height > 32767 ||
        size_t(g.firstVertex) + size_t(g.width) * g.height > mesh.positions.size() ||
        (stored && (g.firstTriangle < next || g.firstTriangle + 2 * cells > mesh.numTriangles())) ||
        (!stored && g.face < 0))
      throw Error("triangle grid at triangle " + std::to_string(g.firstTriangle) +
                  " does not fit the mesh or overlaps another grid");
    if (!stored) {
      gridOnly += 2 * cells;
      continue;
    }
    for (; next < g.firstTriangle; ++next) outside.push_back(static_cast<uint32_t>(next));
    next = g.firstTriangle + 2 * cells;
  }
  for (; next < mesh.numTriangles(); ++next) outside.push_back(static_cast<uint32_t>(next));
  if (gridOnly != mesh.gridOnlyTriangles)
    throw Error("the mesh's grids hold " + std::to_string(gridOnly) +
                " triangles it does not store, not the " + std::to_string(mesh.gridOnlyTriangles) +
                " it counts");
  return outside;
}

// The turn t (0 to 2) of triangle b such that b's corners t + 1 and t + 2 are a's corners 2 and 1
// (b shares a's edge from corner 1 to 2, the other way round, and is not a's mirror image); -1 if
// none.
int turnAcross(const uint32_t* a, const uint32_t* b) {
  for (int t = 0; t < 3; ++t)
    if (b[(t + 1) % 3] == a[2] && b[(t + 2) % 3] == a[1] && b[t] != a[0]) return t;
  return -1;
}

// The mesh triangles outside the grids in cells: each with the next one when the two share an edge
// (in opposite directions, as triangles of a consistently oriented surface do). The stitching
// triangles between a face's edges and its grid come in strips, so most pair up: half the cells,
// Embree primitives and copied points of one cell a triangle.
std::vector<Cell> pairCells(const TessellatedMesh& mesh, const std::vector<uint32_t>& singles) {
  std::vector<Cell> cells;
  cells.reserve(singles.size());
  for (size_t k = 0; k < singles.size();) {
    Cell cell{.lower = singles[k]};
    if (k + 1 < singles.size()) {
      const uint32_t* a = &mesh.indices[3 * size_t(singles[k])];
      const uint32_t* b = &mesh.indices[3 * size_t(singles[k + 1])];
      for (int turn = 0; turn < 3 && cell.upper == Cell::kNone; ++turn) {
        const uint32_t turned[3] = {a[turn], a[(turn + 1) % 3], a[(turn + 2) % 3]};
        const int across = turnAcross(turned, b);
        if (across < 0) continue;
        cell.upper = singles[k + 1];
        cell.lowerTurn = static_cast<uint8_t>(turn);
        cell.upperTurn = static_cast<uint8_t>(across);
      }
    }
    k += cell.upper == Cell::kNone ? 1 : 2;
    cells.push_back(cell);
  }
  return cells;
}

}  // namespace

// One grid geometry holds the blocks and, after them, every other triangle in a 2 x 2 grid, alone
// (the fourth point repeats the third, so Embree's second triangle of that cell has no area) or
// with a neighbour (pairCells): a ray then traverses one BVH instead of a triangle BVH and a grid
// BVH spread over the same surface (measured on a displaced torus: 80% of the all-triangle ray rate
// against 60%).
int RayScene::addMesh(const TessellatedMesh& mesh, const std::vector<TriangleGrid>& blocks) {
  if (blocks.empty() || mesh.numMicropolygons() == 0) return addMesh(mesh);
  return addGrids(mesh, blocks, nullptr);
}

int RayScene::takeMesh(TessellatedMesh& mesh, const std::vector<TriangleGrid>& blocks) {
  const int index = blocks.empty() || mesh.numMicropolygons() == 0
                        ? addMesh(mesh)
                        : addGrids(mesh, blocks, &mesh.positions);
  std::vector<Vec3>().swap(mesh.positions);
  return index;
}

int RayScene::addGrids(const TessellatedMesh& mesh, const std::vector<TriangleGrid>& blocks,
                       std::vector<Vec3>* points) {
  std::vector<TriangleGrid> grids = blocks;
  std::vector<Cell> cells = pairCells(mesh, trianglesOutsideGrids(mesh, grids));
  const int index = impl_->numMeshes++;
  const size_t numPositions = mesh.positions.size();
  const size_t numPoints = numPositions + 4 * cells.size();
  const size_t numGrids = grids.size() + cells.size();
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_GRID);
  Vec3* vertices = nullptr;
  if (points) {
    // The cells' points go after the mesh's, in the room the tessellator left (or in a larger
    // array), with one point more: Embree reads 16 bytes at the last point.
    if (points->capacity() >= numPoints + 1)
      populatePages(points->data() + numPositions, (numPoints + 1 - numPositions) * sizeof(Vec3));
    resizePopulated(*points, numPoints + 1);
    vertices = points->data();
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices, 0,
                               sizeof(Vec3), numPoints);
  } else {
    vertices = static_cast<Vec3*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(Vec3), numPoints));
    if (vertices) {
      adviseHugePages(vertices, numPoints * sizeof(Vec3));
      copyInParallel(vertices, mesh.positions.data(), numPositions * sizeof(Vec3));
    }
  }
  auto* rtcGrids = static_cast<RTCGrid*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, sizeof(RTCGrid), numGrids));
  if (vertices && rtcGrids) {
    adviseHugePages(rtcGrids, numGrids * sizeof(RTCGrid));
    for (size_t k = 0; k < grids.size(); ++k)
      rtcGrids[k] = {.startVertexID = grids[k].firstVertex,
                     .stride = grids[k].width,
                     .width = grids[k].width,
                     .height = grids[k].height};
    // Hundreds of thousands of stitching triangles on a large ground: their fresh pages on every
    // core too.
    const Vec3* from = vertices;  // the mesh's points, where they are now
    tbb::parallel_for(tbb::blocked_range<size_t>(0, cells.size(), 4096),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t k = range.begin(); k != range.end(); ++k) {
                          const Cell& cell = cells[k];
                          const uint32_t* lower = &mesh.indices[3 * size_t(cell.lower)];
                          Vec3* v = vertices + numPositions + 4 * k;
                          for (int i = 0; i < 3; ++i) v[i] = from[lower[(cell.lowerTurn + i) % 3]];
                          v[3] = cell.upper == Cell::kNone
                                     ? v[2]
                                     : from[mesh.indices[3 * size_t(cell.upper) + cell.upperTurn]];
                          rtcGrids[grids.size() + k] = {
                              .startVertexID = static_cast<unsigned>(numPositions + 4 * k),
                              .stride = 2,
                              .width = 2,
                              .height = 2};
                        }
                      });
  }
  std::vector<Vec3> held;
  if (points) {
    heldBytes_ += points->size() * sizeof(Vec3);  // the room beyond is never touched
    held = std::move(*points);                    // the same array, which Embree reads
  }
  impl_->attach(geometry, {.mesh = index,
                           .isGrid = true,
                           .grids = std::move(grids),
                           .cells = std::move(cells),
                           .points = std::move(held)});
  numTriangles_ += mesh.numMicropolygons();
  numPrimitives_ += numGrids;
  return index;
}

void RayScene::commit() {
  rtcCommitScene(impl_->scene);
  impl_->throwIfError();
}

namespace {

// Embree's (u, v) of a grid hit span the whole grid; the cell and the side of its diagonal give
// the mesh triangle (see TriangleGrid) and the barycentrics of its corners 1 and 2.
void gridHit(const TriangleGrid& g, float u, float v, RayHit& hit) {
  const float gu = u * float(g.width - 1), gv = v * float(g.height - 1);
  const int i = std::clamp(static_cast<int>(gu), 0, g.width - 2);
  const int j = std::clamp(static_cast<int>(gv), 0, g.height - 2);
  const float fu = std::clamp(gu - float(i), 0.0f, 1.0f),
              fv = std::clamp(gv - float(j), 0.0f, 1.0f);
  const bool lower = fu + fv <= 1.0f;  // corners (p00, p10, p01), else (p11, p01, p10)
  if (g.firstTriangle == TriangleGrid::kNotInMesh) {
    hit.triangle = -1;
  } else {
    const int first = static_cast<int>(g.firstTriangle) + 2 * (j * (g.width - 1) + i);
    hit.triangle = lower ? first : first + 1;
  }
  hit.b1 = lower ? fu : 1.0f - fu;
  hit.b2 = lower ? fv : 1.0f - fv;
  hit.face = g.face;
  if (g.face < 0) return;
  // The hit triangle's corners' st from the grid's bilinear map, interpolated as the mesh would.
  // Corners (p00, p10, p01) of the lower triangle, (p11, p01, p10) of the upper one.
  const Vec2 c0 = lower ? g.stAt(i, j) : g.stAt(i + 1, j + 1);
  const Vec2 c1 = lower ? g.stAt(i + 1, j) : g.stAt(i, j + 1);
  const Vec2 c2 = lower ? g.stAt(i, j + 1) : g.stAt(i + 1, j);
  hit.st = (1.0f - hit.b1 - hit.b2) * c0 + hit.b1 * c1 + hit.b2 * c2;
}

// Embree's ray for ours: the whole segment [tNear, tFar], every geometry (mask), no motion.
RTCRay toEmbree(const Ray& ray) {
  RTCRay r;
  r.org_x = ray.origin.x;
  r.org_y = ray.origin.y;
  r.org_z = ray.origin.z;
  r.dir_x = ray.direction.x;
  r.dir_y = ray.direction.y;
  r.dir_z = ray.direction.z;
  r.tnear = ray.tNear;
  r.tfar = ray.tFar;
  r.time = 0.0f;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
  return r;
}

RTCRayHit toEmbreeHit(const Ray& ray) {
  RTCRayHit rh;
  rh.ray = toEmbree(ray);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

// Embree's context for a query: coherent rays (a tile's camera rays, shadow rays towards one
// light from a tile's hits) let its stream code trace them in packets.
RTCIntersectContext contextFor(bool coherent) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags =
      coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return context;
}

// Traces `rays` as Embree streams of at most RayScene::kStreamChunk rays held on the stack:
// convert each ray to Embree's, trace(rays, count), then answer(index in `rays`, Embree's ray).
template <class EmbreeRay, class Convert, class Trace, class Answer>
void traceStream(std::span<const Ray> rays, Convert convert, Trace trace, Answer answer) {
  std::array<EmbreeRay, RayScene::kStreamChunk> chunk;
  for (size_t first = 0; first < rays.size(); first += chunk.size()) {
    const size_t n = std::min(chunk.size(), rays.size() - first);
    for (size_t i = 0; i < n; ++i) chunk[i] = convert(rays[first + i]);
    trace(chunk.data(), n);
    for (size_t i = 0; i < n; ++i) answer(first + i, chunk[i]);
  }
}

}  // namespace

bool RayScene::Impl::hitOf(const RTCRayHit& rh, RayHit& hit) const {
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit.t = rh.ray.tfar;
  hit.Ng = Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  const Part& part = parts[rh.hit.geomID];
  hit.mesh = part.mesh;
  if (part.isGrid && rh.hit.primID < part.grids.size()) {
    gridHit(part.grids[rh.hit.primID], rh.hit.u, rh.hit.v, hit);
    return true;
  }
  hit.face = -1;
  if (!part.isGrid) {
    hit.triangle = static_cast<int>(rh.hit.primID);
    hit.b1 = rh.hit.u;
    hit.b2 = rh.hit.v;
    return true;
  }
  // A cell's (u, v) span its 2 x 2 grid: the barycentrics w of its corners (p00, p10, p01) in the
  // lower triangle, of (p11, p01, p10) in the upper one, turned to the mesh triangle's corners; the
  // clamp only guards rounding.
  const Cell& cell = part.cells[rh.hit.primID - part.grids.size()];
  const float u = rh.hit.u, v = rh.hit.v;
  const bool lower = cell.upper == Cell::kNone || u + v <= 1.0f;
  std::array<float, 3> w = lower ? std::array<float, 3>{1.0f - u - v, u, v}
                                 : std::array<float, 3>{u + v - 1.0f, 1.0f - u, 1.0f - v};
  if (w[0] < 0.0f || w[1] < 0.0f || w[2] < 0.0f) {
    for (float& x : w) x = std::max(x, 0.0f);
    const float sum = w[0] + w[1] + w[2];
    for (float& x : w) x /= sum;
  }
  const int turn = lower ? cell.lowerTurn : cell.upperTurn;
  hit.triangle = static_cast<int>(lower ? cell.lower : cell.upper);
  hit.b1 = w[(4 - turn) % 3];
  hit.b2 = w[(5 - turn) % 3];
  return true;
}

bool RayScene::intersect(const Ray& ray, RayHit& hit) const {
  RTCIntersectContext context = contextFor(false);
  RTCRayHit rh = toEmbreeHit(ray);
  rtcIntersect1(impl_->scene, &context, &rh);
  return impl_->hitOf(rh, hit);
}

bool RayScene::occluded(const Ray& ray) const {
  RTCIntersectContext context = contextFor(false);
  RTCRay r = toEmbree(ray);
  // rtcOccluded1 sets tfar to -inf when it finds any hit.
  rtcOccluded1(impl_->scene, &context, &r);
  return r.tfar < 0.0f;
}

void RayScene::intersect(std::span<const Ray> rays, std::span<RayHit> hits,
                         std::span<uint8_t> found, bool coherent) const {
  if (hits.size() < rays.size() || found.size() < rays.size())
    throw std::invalid_argument("RayScene::intersect: fewer hits than rays");
  RTCIntersectContext context = contextFor(coherent);
  traceStream<RTCRayHit>(
      rays, toEmbreeHit,
      [&](RTCRayHit* rh, size_t n) {
        rtcIntersect1M(impl_->scene, &context, rh, static_cast<unsigned>(n), sizeof(RTCRayHit));
      },
      [&](size_t i, const RTCRayHit& rh) { found[i] = impl_->hitOf(rh, hits[i]); });
}

void RayScene::occluded(std::span<const Ray> rays, std::span<uint8_t> occluded,
                        bool coherent) const {
  if (occluded.size() < rays.size())
    throw std::invalid_argument("RayScene::occluded: fewer answers than rays");
  RTCIntersectContext context = contextFor(coherent);
  traceStream<RTCRay>(
      rays, toEmbree,
      [&](RTCRay* r, size_t n) {
        rtcOccluded1M(impl_->scene, &context, r, static_cast<unsigned>(n), sizeof(RTCRay));
      },
      // rtcOccluded1M sets tfar to -inf when it finds any hit.
      [&](size_t i, const RTCRay& r) { occluded[i] = r.tfar < 0.0f; });
}

size_t RayScene::deviceBytes() const {
  return static_cast<size_t>(std::max(0LL, impl_->bytes.load()));
}

size_t RayScene::peakDeviceBytes() const {
  return static_cast<size_t>(std::max(0LL, impl_->peakBytes.load()));
}

}  // namespace meso
