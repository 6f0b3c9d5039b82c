// make sanitize, ThreadSanitizer: Debian's libtbb is not instrumented, so TSan cannot see the
// join of a parallel loop and reports every result a worker wrote and the caller then read.
// Under TSan the suites run TBB's loops on the calling thread (one thread allowed); the threads
// polyloc starts itself (daemon, servers, readers, writers) are still checked against each other.
#if defined(__SANITIZE_THREAD__)
#include <tbb/global_control.h>

namespace {
const tbb::global_control kSerialTbb(tbb::global_control::max_allowed_parallelism, 1);
}  // namespace
#endif
