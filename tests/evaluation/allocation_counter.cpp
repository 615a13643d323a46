// Counts global operator new calls in this test binary (to check "no allocation per frame").
#include "allocation_counter.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

// AddressSanitizer owns operator new/delete (and checks they pair up), so under it the counter
// is not installed and allocation_count() reports -1.
#if defined(__SANITIZE_ADDRESS__)

long vlpground::test::allocation_count() { return -1; }

#else

namespace {
std::atomic<long> g_allocations{0};
}

long vlpground::test::allocation_count() { return g_allocations.load(); }

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return ::operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

#endif
