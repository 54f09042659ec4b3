#include "common/fuzz/fuzz_input.h"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace ephor::fuzz {

FuzzInputFile::FuzzInputFile() {
  fd_ = memfd_create("ephor-fuzz-input", MFD_CLOEXEC);
  if (fd_ < 0) fail("memfd_create failed");
  path_ = "/proc/self/fd/" + std::to_string(fd_);
}

FuzzInputFile::~FuzzInputFile() {
  if (fd_ >= 0) close(fd_);
}

const std::string& FuzzInputFile::write(const uint8_t* data, size_t size) {
  if (ftruncate(fd_, 0) != 0) fail("ftruncate of the fuzz input file failed");
  size_t done = 0;
  while (done < size) {
    const ssize_t n = pwrite(fd_, data + done, size - done, static_cast<off_t>(done));
    if (n <= 0) fail("write of the fuzz input file failed");
    done += static_cast<size_t>(n);
  }
  return path_;
}

FuzzNamedFile::FuzzNamedFile(const std::string& name) {
  std::string dir = (std::filesystem::temp_directory_path() / "ephor-fuzz-XXXXXX").string();
  if (::mkdtemp(dir.data()) == nullptr) fail("cannot make a temporary folder");
  dir_ = dir;
  path_ = dir + "/" + name;
}

FuzzNamedFile::~FuzzNamedFile() {
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

const std::string& FuzzNamedFile::write(const uint8_t* data, size_t size) {
  std::ofstream out(path_, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out) fail("cannot write " + path_);
  return path_;
}

void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace ephor::fuzz
