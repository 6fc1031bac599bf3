// The largest single heap allocation made while a function runs: the io test
// binary's malloc (tests/io/allocation_tracker.cpp) interposes glibc's
// (operator new, Eigen and zlib all end there).
#ifndef SDCB_TESTS_TESTING_ALLOCATION_TRACKER_H_
#define SDCB_TESTS_TESTING_ALLOCATION_TRACKER_H_

#include <cstddef>
#include <functional>

namespace sdcb::testing {

// Runs `f` and returns the largest single malloc request it made (bytes).
size_t LargestAllocationDuring(const std::function<void()>& f);

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_ALLOCATION_TRACKER_H_
