// The Pareto front of time against error (see pareto_front.h).
#include "meso/trade/pareto_front.h"

#include <algorithm>
#include <limits>

namespace meso::trade {

std::vector<size_t> paretoFront(const std::vector<TradeResult>& results) {
  std::vector<size_t> order;
  for (size_t i = 0; i < results.size(); ++i)
    if (results[i].config.kind != Kind::Reference) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const TradeResult &ra = results[a], &rb = results[b];
    return ra.seconds != rb.seconds ? ra.seconds < rb.seconds : ra.errors.rmse < rb.errors.rmse;
  });
  std::vector<size_t> front;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i : order)
    if (results[i].errors.rmse < best) front.push_back(i), best = results[i].errors.rmse;
  return front;
}

}  // namespace meso::trade
