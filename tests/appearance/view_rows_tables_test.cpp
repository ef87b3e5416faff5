// Only the table entries a scene needs (docs/tables.md): a material's coarsest BRDF and
// self-shadowing tables built on some theta_V rows are, on those rows, the whole tables' bits;
// lookups clamp to them; the finer levels stay whole.
#include "meso/appearance/material_tables.h"

#include "support/small_tables.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace meso {
namespace {

Material twoLevels() { return testing::twoNoiseLevels("rows"); }

TableSettings smallSettings() { return testing::smallTableSettings(7); }

// An isotropic class and a stretched one (which derives from the level's tile).
std::vector<MetricClass> twoClasses() {
  return {{1.0f, MetricShape{}}, {1.4f, MetricShape{2.0f, 0.0f}}};
}

MaterialRelief build(ViewRows rows) {
  const TableCache none{std::filesystem::path()};
  return buildMaterialRelief(twoLevels(), none, nullptr, smallSettings(), twoClasses(), nullptr,
                             [rows](const MaterialRelief& r) {
                               // The classes are known when the rows are asked for.
                               EXPECT_EQ(r.metrics.size(), 2u);
                               return std::vector<ViewRows>{rows};
                             });
}

TEST(ViewRowsTables, RowsBuiltAreTheWholeTablesRowsAndLookupsClampToThem) {
  const ViewRows rows{3, 5};
  const MaterialRelief whole = build({}), part = build(rows);
  ASSERT_EQ(part.metrics.size(), 2u);
  for (size_t c = 0; c < 2; ++c) {
    const LevelTables& w = whole.metrics[c].levels[0];
    const LevelTables& p = part.metrics[c].levels[0];
    EXPECT_NE(w.key, p.key) << "the rows are part of the cache key";
    EXPECT_EQ(p.brdf.viewRows(), rows);
    const int phiV = p.brdf.numPhiV(), nV = p.brdf.numThetaV();
    const size_t perRow = w.brdf.data().size() / 2 / nV;
    ASSERT_EQ(w.brdf.data().size(), p.brdf.data().size());
    for (int k = 0; k < nV; ++k)
      for (size_t e = 0; e < perRow; ++e)
        for (size_t half : {size_t(0), w.brdf.data().size() / 2}) {
          const size_t i = half + k * perRow + e;
          if (rows.contains(k))
            ASSERT_EQ(p.brdf.data()[i], w.brdf.data()[i]) << "class " << c << " row " << k;
          else
            ASSERT_EQ(p.brdf.data()[i], 0.0f) << "row " << k << " was not to be integrated";
        }
    ASSERT_EQ(phiV, w.brdf.numPhiV());
    // The self-shadowing factor: the rows' refined nodes are the whole table's, the others 1.
    const int refine = smallSettings().shadowing.thetaVRefine;
    const std::vector<float> ws = w.shadowing.toData(), ps = p.shadowing.toData();
    ASSERT_EQ(ws.size(), ps.size());
    const int nS = w.shadowing.numThetaV();
    const size_t head = 2 + static_cast<size_t>(nS), body = (ws.size() - head) / 2,
                 perNode = body / nS;
    int untraced = 0;
    for (int k = 0; k < nS; ++k)
      for (size_t e = 0; e < perNode; ++e)
        for (size_t half : {size_t(0), body}) {
          const size_t i = head + half + k * perNode + e;
          if (k >= rows.first * refine && k <= rows.last * refine)
            ASSERT_EQ(ps[i], ws[i]) << "class " << c << " node " << k;
          else
            untraced += ps[i] != ws[i];
        }
    EXPECT_GT(untraced, 0) << "the rows outside were traced anyway";
    // Lookups: the whole table's inside the rows, the nearest row's beyond them.
    const float lo = p.brdf.thetaV(rows.first), hi = p.brdf.thetaV(rows.last);
    for (float tl : {0.3f, 0.9f, 1.4f})
      for (float phiVL : {-2.0f, 0.4f, 3.0f}) {
        for (float t = 0.0f; t <= 1.0f; t += 0.125f) {
          const float tv = lo + t * (hi - lo);
          const BrdfTable::Value a = w.brdf.lookup(tv, 0.7f, tl, phiVL);
          const BrdfTable::Value b = p.brdf.lookup(tv, 0.7f, tl, phiVL);
          EXPECT_EQ(a.diffuse, b.diffuse);
          EXPECT_EQ(a.specular, b.specular);
          const ShadowingTable::Value sa = w.shadowing.lookup(tv, 0.7f, tl, phiVL);
          const ShadowingTable::Value sb = p.shadowing.lookup(tv, 0.7f, tl, phiVL);
          EXPECT_EQ(sa.diffuse, sb.diffuse);
          EXPECT_EQ(sa.specular, sb.specular);
        }
        // (The whole table located at a node's angle may land a rounding short of it.)
        EXPECT_NEAR(p.brdf.lookup(0.05f, 0.7f, tl, phiVL).diffuse,
                    w.brdf.lookup(lo, 0.7f, tl, phiVL).diffuse, 1e-6f);
        EXPECT_NEAR(p.brdf.lookup(1.5f, 0.7f, tl, phiVL).specular,
                    w.brdf.lookup(hi, 0.7f, tl, phiVL).specular, 1e-6f);
        EXPECT_NE(p.brdf.lookup(1.5f, 0.7f, tl, phiVL).specular,
                  w.brdf.lookup(1.5f, 0.7f, tl, phiVL).specular);
      }
    // The finer level is whole: the coarser one's eq. (1) looks it up at any angle.
    const LevelTables& wf = whole.metrics[c].levels[1];
    const LevelTables& pf = part.metrics[c].levels[1];
    EXPECT_EQ(wf.key, pf.key);
    EXPECT_TRUE(pf.brdf.viewRows().all());
    EXPECT_EQ(wf.brdf.data(), pf.brdf.data());
  }
}

}  // namespace
}  // namespace meso
