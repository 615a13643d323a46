#include "file_output.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace vlpground::mcap::detail {

std::uint32_t crc32(std::uint32_t crc, std::span<const std::byte> bytes) {
  auto value = static_cast<uLong>(crc);
  const auto* data = reinterpret_cast<const Bytef*>(bytes.data());
  std::size_t left = bytes.size();
  while (left > 0) {  // zlib takes uInt lengths
    const std::size_t n = std::min<std::size_t>(left, std::numeric_limits<uInt>::max());
    value = ::crc32(value, data, static_cast<uInt>(n));
    data += n;
    left -= n;
  }
  return static_cast<std::uint32_t>(value);
}

FileOutput::~FileOutput() {
  if (fd_ >= 0) ::close(fd_);
}

void FileOutput::fail(const char* what) {
  const int error = errno;
  failed_ = true;
  errno = error;
  throw std::runtime_error("mcap: cannot " + std::string(what) + " '" + path_ +
                           "': " + std::strerror(errno));
}

void FileOutput::open(const std::string& path) {
  path_ = path;
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) fail("create");
  failed_ = false;
  offset_ = 0;
  crc_ = 0;
}

void FileOutput::write(std::span<const std::byte> bytes) {
  const auto* data = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd_, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("write");
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  offset_ += bytes.size();
  crc_ = crc32(crc_, bytes);
}

void FileOutput::sync() {
  if (::fsync(fd_) != 0) fail("sync");
}

void FileOutput::close() {
  if (fd_ < 0) return;
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail("close");
}

}  // namespace vlpground::mcap::detail
