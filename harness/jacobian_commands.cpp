// jacobian, singular: registered by the Jacobian/singularity work (issue 4).
#include "commands.hpp"

namespace lowpair {
void addJacobianCommands(CLI::App&, Commands&) {}
}  // namespace lowpair
