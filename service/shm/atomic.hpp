// Atomic access to fields of the shared segment. The fields are plain integers in C structs
// (service/shm/include/polyloc_shm.h) shared between processes, so they are accessed with the __atomic
// builtins (naturally aligned, lock-free) rather than std::atomic members: the C layout stays
// the definition. Every access to a word that another process writes goes through here.
#pragma once

#include <cstdint>
#include <type_traits>

namespace polyloc::shm::atomic {

template <class T> inline T loadAcquire(const T* p) { return __atomic_load_n(p, __ATOMIC_ACQUIRE); }
template <class T> inline T loadRelaxed(const T* p) { return __atomic_load_n(p, __ATOMIC_RELAXED); }
template <class T> inline void storeRelease(T* p, std::type_identity_t<T> v) { __atomic_store_n(p, v, __ATOMIC_RELEASE); }
template <class T> inline void storeRelaxed(T* p, std::type_identity_t<T> v) { __atomic_store_n(p, v, __ATOMIC_RELAXED); }
// Sequentially consistent: a publish (write_count, notify, doorbell) must not pass the wake-up
// check of a waiter in the other order.
template <class T> inline T fetchAdd(T* p, std::type_identity_t<T> v) { return __atomic_fetch_add(p, v, __ATOMIC_SEQ_CST); }
template <class T> inline bool compareExchange(T* p, T& expected, std::type_identity_t<T> desired) {
  return __atomic_compare_exchange_n(p, &expected, desired, false, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE);
}
inline void fenceAcquire() { __atomic_thread_fence(__ATOMIC_ACQUIRE); }
inline void fenceRelease() { __atomic_thread_fence(__ATOMIC_RELEASE); }

// A hint to the CPU inside spin loops (keeps the sibling hyper-thread and the bus quiet).
inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  __asm__ __volatile__("yield");
#endif
}

}  // namespace polyloc::shm::atomic
