#include "lowpair/measure.hpp"

namespace lowpair {

const char* measureName(Measure measure) {
  switch (measure) {
    case Measure::Pose: return "pose";
    case Measure::Position: return "position";
    case Measure::Targets: return "targets";
  }
  return "pose";
}

}  // namespace lowpair
