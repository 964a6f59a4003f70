// Errors as values with a location (STYLE.md habit 11): library code never exits; it returns an
// Error naming the file, the JSON pointer (or other location), the message and the valid choices.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace hdrc {

// A number as error messages show it: 9 significant digits (printf's %.9g).
std::string format_number(double v);

struct Error {
  std::string file;     // the file the problem is in ("" when none)
  std::string pointer;  // JSON pointer or other location inside the file ("" when none)
  std::string message;  // what is wrong, including the offending value
  std::string choices;  // the valid choices ("" when there is no closed set)

  // "file: /pointer: message; valid choices: ..." — the one format every error is printed in.
  std::string to_string() const;
};

template <typename T>
class Result {
 public:
  Result(T value) : v_(std::move(value)) {}      // NOLINT: implicit by design
  Result(Error error) : v_(std::move(error)) {}  // NOLINT
  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() { return std::get<0>(v_); }
  const T& value() const { return std::get<0>(v_); }
  T& operator*() { return value(); }
  const T& operator*() const { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  const Error& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, Error> v_;
};

// Result<void> equivalent.
class Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const Error& error() const { return error_; }

 private:
  Error error_;
  bool ok_ = true;
};

}  // namespace hdrc
