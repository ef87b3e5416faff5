#include "meso/appearance/table_plots.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace meso {
namespace {

// The rows of a CSV after its header, each as numbers; the header in *header.
std::vector<std::vector<double>> rowsOf(const std::string& csv, std::string* header) {
  std::istringstream in(csv);
  std::getline(in, *header);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<double> row;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

// One row per bin of every theta_V slice; a slice's densities times their bins' solid angles sum to
// its mass (1 after normalize()), so the plot shows densities, not masses.
TEST(TablePlots, HistogramCsvHoldsEveryBinAsADensity) {
  VisibleNormalHistogram h(HistogramResolution{6, 8, 10});
  for (int k = 0; k < 6; ++k) h.add(k, glm::normalize(Vec3(0.1f * k, 0.0f, 1.0f)));
  h.normalize();
  std::string header;
  const auto rows = rowsOf(histogramCsv(h), &header);
  EXPECT_EQ(header, "theta_v_deg,theta_n_deg,phi_deg,density");
  ASSERT_EQ(rows.size(), 6u * 8u * 10u);
  for (int k = 0; k < 6; ++k) {
    double mass = 0.0;
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 10; ++j) {
        const std::vector<double>& row = rows[(k * 8 + i) * 10 + j];
        ASSERT_EQ(row.size(), 4u);
        EXPECT_NEAR(row[0], degrees(h.thetaV(k)), 1e-3);
        EXPECT_GT(row[1], 0.0);
        EXPECT_LT(row[1], 90.0);
        EXPECT_GE(row[2], -180.0);
        EXPECT_LT(row[2], 180.0);
        mass += row[3] * h.solidAngle(i);
      }
    EXPECT_NEAR(mass, 1.0, 1e-4) << "theta_V slice " << k;
  }
}

// theta_L over [0, 90] and phi_{V-L} over [0, 180] for every theta_V; the brightest diffuse cell of
// the nearly flat relief is the light at the zenith.
TEST(TablePlots, BrdfCsvHoldsEveryNodeOfTheUpperHemisphere) {
  VisibleNormalHistogram h(HistogramResolution{6, 8, 10});
  for (int k = 0; k < 6; ++k) h.add(k, glm::normalize(Vec3(0.1f * k, 0.0f, 1.0f)));
  h.normalize();
  const BrdfTable b = BrdfTable::fromDistribution(h, {5, 4}, 10.0f);
  std::string header;
  const auto rows = rowsOf(brdfCsv(b), &header);
  EXPECT_EQ(header, "theta_v_deg,theta_l_deg,phi_deg,diffuse,specular");
  ASSERT_EQ(rows.size(), static_cast<size_t>(b.numThetaV()) * 5u * 4u);
  double maxThetaL = 0.0, maxPhi = 0.0, brightest = -1.0, brightestThetaL = -1.0;
  for (const std::vector<double>& row : rows) {
    ASSERT_EQ(row.size(), 5u);
    for (double v : row) EXPECT_TRUE(std::isfinite(v));
    maxThetaL = std::max(maxThetaL, row[1]);
    maxPhi = std::max(maxPhi, row[2]);
    if (row[3] > brightest) brightest = row[3], brightestThetaL = row[1];
  }
  EXPECT_NEAR(maxThetaL, 90.0, 1e-3);
  EXPECT_NEAR(maxPhi, 180.0, 1e-3);
  EXPECT_NEAR(brightestThetaL, 0.0, 1e-3);
}

}  // namespace
}  // namespace meso
