// The images build their objects in static storage and never allocate. Virtual destructors still
// bring deleting destructors, and with them calls to operator delete; these free nothing.
#include <cstddef>

void operator delete(void*) noexcept {}
void operator delete(void*, std::size_t) noexcept {}
