// placeholder: being written
#include "commands.hpp"
namespace lowpair {
void addExportCommand(CLI::App&, Commands&) {}
}  // namespace lowpair
