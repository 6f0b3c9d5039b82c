// make sanitize, AddressSanitizer: Mesa's software driver keeps a one-time allocation of its own
// from eglInitialize and is unloaded by eglTerminate, so at exit LeakSanitizer's (fast) unwinder
// finds the allocation's caller in no module and tests/sanitize/lsan.supp cannot name it. Under
// ASan the suites load the driver once more, never to be unloaded (RTLD_NODELETE): its frames
// keep their library's name. (DWARF unwinding, fast_unwind_on_malloc=0, would name it too, but
// deadlocks in libgcc's unwinder while LLVM registers the JIT's frames.)
#if defined(__SANITIZE_ADDRESS__)
#include <dlfcn.h>

namespace {
const bool kMesaResident = [] {
  for (const char* so : {"/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so", "/usr/lib/aarch64-linux-gnu/dri/swrast_dri.so",
                         "/usr/lib/dri/swrast_dri.so"})
    if (dlopen(so, RTLD_LAZY | RTLD_NODELETE)) return true;
  return false;
}();
}  // namespace
#endif
