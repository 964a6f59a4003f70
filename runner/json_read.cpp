#include "runner/json_read.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/utf8.h"

namespace hdrc {

Result<std::string> read_bounded_file(const std::string& path, size_t max_bytes,
                                      const std::string& what) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; the type is checked right after.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    const int err = errno;
    return Error{
        valid_utf8(path), "",
        "cannot open " + what + ": " + std::strerror(err) + (err == ENOENT ? "" : " (it exists)"),
        ""};
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return Error{valid_utf8(path), "", what + " is not a regular file", "a regular file"};
  }
  if (static_cast<unsigned long long>(st.st_size) > max_bytes) {
    ::close(fd);
    return Error{valid_utf8(path), "",
                 what + " is " + std::to_string(st.st_size) + " bytes, over the limit",
                 "at most " + std::to_string(max_bytes) + " bytes"};
  }
  std::string text;
  text.resize(static_cast<size_t>(st.st_size));
  size_t got = 0;
  // Bounded by max_bytes: a file that grows while read is read up to its size at fstat time + 1
  // byte to notice the growth.
  for (;;) {
    if (got == text.size()) {
      if (text.size() >= max_bytes) break;
      text.resize(std::min(max_bytes, text.size() + 4096));
    }
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      return Error{valid_utf8(path), "", "cannot read " + what + ": " + std::strerror(err), ""};
    }
    if (n == 0) break;
    got += static_cast<size_t>(n);
  }
  ::close(fd);
  text.resize(got);
  return text;
}

Status check_json_nesting(const std::string& file, const std::string& text) {
  int depth = 0;
  size_t line = 1;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') ++line;
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        return Error{valid_utf8(file), "line " + std::to_string(line),
                     "JSON nested more than " + std::to_string(kMaxJsonDepth) + " levels deep",
                     "at most " + std::to_string(kMaxJsonDepth) + " nested arrays/objects"};
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return {};
}

}  // namespace hdrc
