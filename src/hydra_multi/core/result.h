#pragma once
// One vocabulary for failure that callers must look at: a Result<T> is a value or an error message;
// a Status is success or an error message. Bad input (a malformed file, a corrupt robot update) is
// reported through these, never through a crash.

#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

namespace hydra_multi {

/// An error message that says what was wrong and where.
struct Error {
  std::string message;
};

/// Success, or an error message.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error)
      : message_(std::move(error.message)), ok_(false) {}  // NOLINT: implicit on purpose
  static Status Ok() { return {}; }

  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  /// The error message; empty on success.
  const std::string& message() const { return message_; }

 private:
  std::string message_;
  bool ok_ = true;
};

/// A value of type T, or an error message.
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : data_(std::move(value)) {}      // NOLINT: implicit on purpose
  Result(Error error) : data_(std::move(error)) {}  // NOLINT: implicit on purpose

  bool ok() const { return std::holds_alternative<T>(data_); }
  explicit operator bool() const { return ok(); }

  /// The value; throws std::logic_error when this holds an error (a caller's bug).
  const T& value() const& { return checked(); }
  T& value() & { return checked(); }
  T&& value() && { return std::move(checked()); }

  /// The error message; empty when this holds a value.
  const std::string& error() const {
    static const std::string kNone;
    return ok() ? kNone : std::get<Error>(data_).message;
  }
  Status status() const { return ok() ? Status::Ok() : Status(std::get<Error>(data_)); }

 private:
  T& checked() const {
    if (!ok()) throw std::logic_error("Result::value() on an error: " + error());
    return const_cast<T&>(std::get<T>(data_));
  }
  std::variant<T, Error> data_;
};

}  // namespace hydra_multi
