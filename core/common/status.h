// Status values for everything the library can be asked to do with bad input.
// Libraries never abort or print on bad input: they return a Status (or a
// StatusOr<T>) and the caller, usually the CLI, turns it into a message and an
// exit code. Modeled on Draco's Status / StatusOr.
#ifndef SDCB_CORE_COMMON_STATUS_H_
#define SDCB_CORE_COMMON_STATUS_H_

#include <optional>
#include <string>
#include <utility>

namespace sdcb {

enum class StatusCode {
  kOk = 0,
  kInvalidArgument,  // A caller passed a value outside the documented range.
  kIoError,          // A file could not be opened, read, written or renamed.
  kInvalidInput,     // The data is readable but unusable (bad mesh, NaN, ...).
  kCorruptFile,      // A file is malformed, truncated or fails its checks.
  kUnsupported,      // A valid input the method cannot handle (e.g. genus 3).
  kInternal,         // A numerical or logic failure inside the library.
};

class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message)
      : code_(code), message_(std::move(message)) {}
  static Status Ok() { return Status(); }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  // One sentence, without a trailing newline.
  const std::string& message() const { return message_; }

  // Returns a copy whose message is "prefix: message" (e.g. a file name).
  Status WithPrefix(const std::string& prefix) const {
    if (ok()) return *this;
    return Status(code_, prefix + ": " + message_);
  }

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

inline Status InvalidArgumentError(std::string m) {
  return Status(StatusCode::kInvalidArgument, std::move(m));
}
inline Status IoError(std::string m) {
  return Status(StatusCode::kIoError, std::move(m));
}
inline Status InvalidInputError(std::string m) {
  return Status(StatusCode::kInvalidInput, std::move(m));
}
inline Status CorruptFileError(std::string m) {
  return Status(StatusCode::kCorruptFile, std::move(m));
}
inline Status UnsupportedError(std::string m) {
  return Status(StatusCode::kUnsupported, std::move(m));
}
inline Status InternalError(std::string m) {
  return Status(StatusCode::kInternal, std::move(m));
}

// Either a value or a non-ok Status.
template <typename T>
class [[nodiscard]] StatusOr {
 public:
  StatusOr(const Status& status) : status_(status) {}  // NOLINT: implicit
  StatusOr(T value) : value_(std::move(value)) {}      // NOLINT: implicit

  bool ok() const { return status_.ok(); }
  const Status& status() const { return status_; }
  const T& value() const& { return *value_; }
  T& value() & { return *value_; }
  T&& value() && { return std::move(*value_); }
  const T& operator*() const& { return *value_; }
  T& operator*() & { return *value_; }
  const T* operator->() const { return &*value_; }
  T* operator->() { return &*value_; }

 private:
  Status status_;
  std::optional<T> value_;
};

}  // namespace sdcb

#define SDCB_STATUS_CONCAT_INNER_(a, b) a##b
#define SDCB_STATUS_CONCAT_(a, b) SDCB_STATUS_CONCAT_INNER_(a, b)

// Returns from the current function if `expr` yields a non-ok Status.
#define SDCB_RETURN_IF_ERROR(expr)               \
  do {                                           \
    const ::sdcb::Status sdcb_status_ = (expr);  \
    if (!sdcb_status_.ok()) return sdcb_status_; \
  } while (0)

// `lhs` = value of the StatusOr `expr`, or return its Status.
#define SDCB_ASSIGN_OR_RETURN(lhs, expr)                                    \
  SDCB_ASSIGN_OR_RETURN_IMPL_(SDCB_STATUS_CONCAT_(sdcb_or_, __LINE__), lhs, \
                              expr)
#define SDCB_ASSIGN_OR_RETURN_IMPL_(tmp, lhs, expr) \
  auto tmp = (expr);                                \
  if (!tmp.ok()) return tmp.status();               \
  lhs = std::move(tmp).value()

#endif  // SDCB_CORE_COMMON_STATUS_H_
