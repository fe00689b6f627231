// The core reports every failure as nd::Error (a status code of the public
// header and a message naming the argument); src/capi turns it into a return
// value and nd_last_error(). Nothing else crosses the C boundary.
#pragma once
#include <exception>
#include <string>

namespace nd {

class Error : public std::exception {
 public:
  Error(int code, std::string message) : code_(code), message_(std::move(message)) {}
  int code() const noexcept { return code_; }
  const char *what() const noexcept override { return message_.c_str(); }

 private:
  int code_;
  std::string message_;
};

[[noreturn]] inline void fail(int code, std::string message) {
  throw Error(code, std::move(message));
}

}  // namespace nd
