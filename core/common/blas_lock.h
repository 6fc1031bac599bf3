// The lock every call into the BLAS holds. sdcb links the serial OpenBLAS
// (Debian's libopenblas0-serial), which keeps its work buffers without
// locks: two threads in it at once corrupt each other's results (two
// concurrent dpotrf of the same matrix return different factors). CHOLMOD's
// supernodal factorizations and solves (core/fit/least_squares.cpp,
// core/fit/fold_repair.cpp) hold it, so parts fitted in parallel factor one
// at a time; nothing else in sdcb calls the BLAS.
#ifndef SDCB_CORE_COMMON_BLAS_LOCK_H_
#define SDCB_CORE_COMMON_BLAS_LOCK_H_

#include <mutex>

namespace sdcb {

std::mutex& BlasMutex();

}  // namespace sdcb

#endif  // SDCB_CORE_COMMON_BLAS_LOCK_H_
