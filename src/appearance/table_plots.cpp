// The data of `meso tables`' plots (table_plots.h).
#include "meso/appearance/table_plots.h"

#include "meso/core/math.h"

#include <fmt/format.h>

namespace meso {

std::string histogramCsv(const VisibleNormalHistogram& h) {
  const HistogramResolution& r = h.resolution();
  std::string csv = "theta_v_deg,theta_n_deg,phi_deg,density\n";
  for (int k = 0; k < r.thetaV; ++k) {
    const int slice = h.sliceOf(k, 0);
    for (int i = 0; i < r.thetaN; ++i)
      for (int j = 0; j < r.phi; ++j)
        csv += fmt::format("{:.6g},{:.6g},{:.6g},{:.6g}\n", degrees(h.thetaV(k)),
                           degrees(h.thetaNCentre(i)), degrees(h.phiCentre(j)),
                           h.mass(slice, i, j) / h.solidAngle(i));
  }
  return csv;
}

std::string brdfCsv(const BrdfTable& b) {
  const BrdfResolution& r = b.resolution();
  std::string csv = "theta_v_deg,theta_l_deg,phi_deg,diffuse,specular\n";
  // With view-azimuth slices phi_{V-L} spans [-180, 180]: its [0, 180] half starts at node
  // r.phi - 1.
  const int pv = b.numPhiV(), j0 = pv > 1 ? r.phi - 1 : 0;
  for (int k = 0; k < b.numThetaV(); ++k)
    for (int i = 0; i < r.thetaL; ++i)
      for (int j = 0; j < r.phi; ++j) {
        const BrdfTable::Value v = b.entry(k * pv, i, j0 + j);
        csv += fmt::format("{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", degrees(b.thetaV(k)),
                           degrees(b.thetaL(i)), degrees(b.phi(j0 + j)), v.diffuse, v.specular);
      }
  return csv;
}

}  // namespace meso
