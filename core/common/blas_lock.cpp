#include "sdcb/core/common/blas_lock.h"

namespace sdcb {

std::mutex& BlasMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace sdcb
