// A fresh scratch directory per test, under SDCB_TEST_TMP.
#ifndef SDCB_TESTS_TESTING_TEMP_DIR_H_
#define SDCB_TESTS_TESTING_TEMP_DIR_H_

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace sdcb::testing {

// Returns SDCB_TEST_TMP/<suite>.<test>, emptied.
inline std::string FreshTestDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      std::filesystem::path(SDCB_TEST_TMP) /
      (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

inline void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline std::string MeshPath(const std::string& name) {
  return std::string(SDCB_MESH_DIR) + "/" + name;
}

// A file of tests/data/ (files kept in the repository).
inline std::string TestDataPath(const std::string& name) {
  return std::string(SDCB_TEST_DATA_DIR) + "/" + name;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_TEMP_DIR_H_
