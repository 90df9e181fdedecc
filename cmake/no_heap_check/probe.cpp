// Deliberately bad code for testing cmake/NoHeapCheck.cmake: it is compiled into a static
// library that no image links, and the check must reject it. Each function commits one of
// the offences the images must be free of.
#include <cstdlib>
#include <typeinfo>

namespace no_heap_check_probe {

struct Base {
  virtual ~Base() = default;
};
struct Derived : Base {};

void* uses_malloc(std::size_t n) { return std::malloc(n); }
void uses_free(void* p) { std::free(p); }
int* uses_new() { return new int(1); }
void uses_delete(int* p) { delete p; }
void throws(int v) {
  if (v != 0) throw v;
}
int catches(int v) {
  try {
    throws(v);
  } catch (int e) {
    return e;
  }
  return 0;
}
const char* uses_rtti(const Base& b) { return typeid(b).name(); }

}  // namespace no_heap_check_probe
