// Result<T> and Status: a value or a one-line error message, returned across
// library boundaries instead of throwing (no exception crosses a library
// boundary). One type for every library: burrlab::base is at the root of the
// dependency graph and every library links it.
#ifndef BURRLAB_BASE_RESULT_H_
#define BURRLAB_BASE_RESULT_H_

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace burrlab {

// A human-readable error, one line, naming what is wrong and where.
struct Error {
  std::string message;
};

// Either a T or an Error. Check ok() before value().
template <typename T>
class [[nodiscard]] Result {
 public:
  // A successful result holding `value`.
  Result(T value)
      : v_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  // A failed result holding `error`.
  Result(Error error)
      : v_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  // True when a value is held.
  bool ok() const { return v_.index() == 0; }
  // Same as ok().
  explicit operator bool() const { return ok(); }

  // The value; only when ok().
  T& value() & {
    assert(ok());
    return std::get<0>(v_);
  }
  // The value; only when ok().
  const T& value() const& {
    assert(ok());
    return std::get<0>(v_);
  }
  // The value, moved out; only when ok().
  T&& value() && {
    assert(ok());
    return std::get<0>(std::move(v_));
  }
  // The error; only when !ok().
  const Error& error() const {
    assert(!ok());
    return std::get<1>(v_);
  }
  // Member access to the value; only when ok().
  T* operator->() { return &value(); }
  // Member access to the value; only when ok().
  const T* operator->() const { return &value(); }
  // The value; only when ok().
  T& operator*() & { return value(); }
  // The value; only when ok().
  const T& operator*() const& { return value(); }

 private:
  std::variant<T, Error> v_;
};

// Result<void>: success or an Error.
class [[nodiscard]] Status {
 public:
  // Success.
  Status() = default;
  // Failure with `error`.
  Status(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT
  // True on success.
  bool ok() const { return ok_; }
  // Same as ok().
  explicit operator bool() const { return ok_; }
  // The error; meaningful only when !ok().
  const Error& error() const { return error_; }

 private:
  Error error_;
  bool ok_ = true;
};

}  // namespace burrlab

#endif  // BURRLAB_BASE_RESULT_H_
