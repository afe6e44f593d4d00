// Linked with one room of the harness as a whole archive and only the rooms below it
// (tests/CMakeLists.txt): the build fails if the room calls into a room above it.
int main() { return 0; }
