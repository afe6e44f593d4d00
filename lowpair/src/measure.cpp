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

const char* measurementsText(Measure measure) {
  switch (measure) {
    case Measure::Pose: return "pose measurements";
    case Measure::Position: return "position measurements";
    case Measure::Targets: return "target measurements";
  }
  return "pose measurements";
}

}  // namespace lowpair
