#pragma once
// ScratchDir: a directory of the test's own under the system's temporary directory (mkdtemp, so
// two test runs at once never share a file), removed with everything in it when it goes out of
// scope. Tests write their files here, never under fixed names in /tmp.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace lasonic::fixture {

class ScratchDir {
 public:
  explicit ScratchDir(const std::string& prefix = "lasonic-test")
      : path_((std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string()) {
    if (::mkdtemp(path_.data()) == nullptr) ADD_FAILURE() << "mkdtemp " << path_ << " failed";
  }
  ~ScratchDir() {
    std::error_code ec;  // nothing to do about a failure while a test ends
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::string& path() const { return path_; }
  // The path of a file NAME in it.
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

}  // namespace lasonic::fixture
