// Numeric constants shared across the library.
#ifndef SDCB_CORE_COMMON_CONSTANTS_H_
#define SDCB_CORE_COMMON_CONSTANTS_H_

namespace sdcb {

constexpr double kPi = 3.14159265358979323846;

}  // namespace sdcb

#endif  // SDCB_CORE_COMMON_CONSTANTS_H_
