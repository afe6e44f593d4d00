#include "lowpair/robust_loss.hpp"

#include <cmath>

namespace lowpair {

const char* lossName(Loss loss) {
  switch (loss) {
    case Loss::Squared: return "squared";
    case Loss::Huber: return "huber";
    case Loss::Cauchy: return "cauchy";
  }
  return "squared";
}

double RobustLoss::rho(double u) const {
  switch (kind) {
    case Loss::Squared: return u * u;
    case Loss::Huber: return u <= scale ? u * u : 2.0 * scale * u - scale * scale;
    case Loss::Cauchy: return scale * scale * std::log1p((u / scale) * (u / scale));
  }
  return u * u;
}

double RobustLoss::weight(double u) const {
  switch (kind) {
    case Loss::Squared: return 1.0;
    case Loss::Huber: return u <= scale ? 1.0 : scale / u;
    case Loss::Cauchy: return 1.0 / (1.0 + (u / scale) * (u / scale));
  }
  return 1.0;
}

}  // namespace lowpair
