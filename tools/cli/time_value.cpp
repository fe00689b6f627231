#include "time_value.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace ndcli {

Expression::Expression(double constant) { ops_.push_back({kNumber, constant}), stack_ = 1; }

// Recursive descent over
//   sum     = product { ("+" | "-") product }
//   product = signed { ("*" | "/") signed }
//   signed  = ("+" | "-") signed | power
//   power   = atom [ "^" signed ]              (right-associative: 2^3^2 = 2^9; -2^2 = -4)
//   atom    = number | "t" | "pi" | name "(" sum ")" | "(" sum ")"
// emitting postfix; every rule that can nest counts against kMaxDepth, so
// that no text, however long or deep, exhausts the stack.
class ExpressionParser {
 public:
  explicit ExpressionParser(std::string_view text) : s_(text) {}

  Expression run() {
    if (s_.size() > Expression::kMaxLength)
      fail(Expression::kMaxLength, "longer than " + std::to_string(Expression::kMaxLength) + " characters");
    skip();
    if (i_ == s_.size()) fail(i_, "empty");
    sum();
    skip();
    if (i_ != s_.size()) fail(i_, std::string("unexpected '") + s_[i_] + "'");
    // the stack's depth, to check evaluation never needs more than it holds
    int depth = 0;
    for (const Expression::Op &op : e_.ops_) {
      depth += op.code <= Expression::kT ? 1 : op.code <= Expression::kPow ? -1 : 0;
      e_.stack_ = std::max(e_.stack_, depth);
      if (op.code == Expression::kT) e_.constant_ = false;
    }
    return std::move(e_);
  }

 private:
  [[noreturn]] void fail(size_t at, const std::string &what) const {
    throw std::invalid_argument("at character " + std::to_string(at + 1) + ": " + what);
  }
  void skip() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t')) ++i_;
  }
  bool take(char c) {
    skip();
    if (i_ < s_.size() && s_[i_] == c) return ++i_, true;
    return false;
  }
  void emit(Expression::Code c, double x = 0) { e_.ops_.push_back({c, x}); }
  struct Nest {  // one level of nesting while it lives
    ExpressionParser &p;
    explicit Nest(ExpressionParser &q) : p(q) {
      if (++p.depth_ > Expression::kMaxDepth)
        p.fail(p.i_, "nested more than " + std::to_string(Expression::kMaxDepth) + " deep");
    }
    ~Nest() { --p.depth_; }
  };

  void sum() {
    product();
    for (;;) {
      if (take('+')) product(), emit(Expression::kAdd);
      else if (take('-')) product(), emit(Expression::kSub);
      else return;
    }
  }
  void product() {
    signed_value();
    for (;;) {
      if (take('*')) signed_value(), emit(Expression::kMul);
      else if (take('/')) signed_value(), emit(Expression::kDiv);
      else return;
    }
  }
  void signed_value() {
    if (take('-')) {
      Nest n(*this);
      return signed_value(), emit(Expression::kNeg);
    }
    if (take('+')) {
      Nest n(*this);
      return signed_value();
    }
    power();
  }
  void power() {
    atom();
    if (take('^')) {
      Nest n(*this);
      signed_value();
      emit(Expression::kPow);
    }
  }
  void atom() {
    skip();
    if (i_ == s_.size()) fail(i_, "a number, t, pi, a function or '(' is missing at the end");
    const char c = s_[i_];
    if (c == '(') {
      Nest n(*this);
      ++i_;
      sum();
      if (!take(')')) fail(i_, "')' expected");
      return;
    }
    if ((c >= '0' && c <= '9') || c == '.') return number();
    if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_') return name();
    fail(i_, std::string("unexpected '") + (static_cast<unsigned char>(c) < 0x20 || c == 0x7F ? '?' : c) +
                 "' (an expression has numbers, t, pi, sin cos exp sqrt, + - * / ^ and parentheses)");
  }
  void number() {
    const size_t start = i_;
    auto digits = [&] {
      size_t k = 0;
      while (i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9') ++i_, ++k;
      return k;
    };
    size_t n = digits();
    if (i_ < s_.size() && s_[i_] == '.') ++i_, n += digits();
    if (n == 0) fail(start, "a number needs digits");
    if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
      ++i_;
      if (i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-')) ++i_;
      if (digits() == 0) fail(i_, "an exponent needs digits");
    }
    double x = 0;
    const auto r = std::from_chars(s_.data() + start, s_.data() + i_, x);  // (no locale)
    if (r.ec != std::errc() || r.ptr != s_.data() + i_ || !std::isfinite(x))
      fail(start, "the number '" + std::string(s_.substr(start, i_ - start)) + "' is out of range");
    emit(Expression::kNumber, x);
  }
  void name() {
    const size_t start = i_;
    while (i_ < s_.size() && ((s_[i_] >= 'a' && s_[i_] <= 'z') || (s_[i_] >= 'A' && s_[i_] <= 'Z') ||
                              (s_[i_] >= '0' && s_[i_] <= '9') || s_[i_] == '_'))
      ++i_;
    const std::string_view w = s_.substr(start, i_ - start);
    if (w == "t") return emit(Expression::kT);
    if (w == "pi") return emit(Expression::kNumber, 3.14159265358979323846);
    const Expression::Code f = w == "sin" ? Expression::kSin : w == "cos" ? Expression::kCos
                             : w == "exp" ? Expression::kExp : w == "sqrt" ? Expression::kSqrt : Expression::kNumber;
    if (f == Expression::kNumber)
      fail(start, "unknown name '" + std::string(w.substr(0, 32)) + "' (known: t, pi, sin, cos, exp, sqrt)");
    Nest n(*this);
    if (!take('(')) fail(i_, "'(' expected after " + std::string(w));
    sum();
    if (!take(')')) fail(i_, "')' expected");
    emit(f);
  }

  std::string_view s_;
  size_t i_ = 0;
  int depth_ = 0;
  Expression e_;
};

Expression Expression::parse(std::string_view text) { return ExpressionParser(text).run(); }

double Expression::at(double t) const {
  double stack[kMaxLength + 1];  // (at most one value per character: stack_ <= kMaxLength)
  int n = 0;
  for (const Op &op : ops_) {
    switch (op.code) {
      case kNumber: stack[n++] = op.x; break;
      case kT: stack[n++] = t; break;
      case kAdd: --n, stack[n - 1] += stack[n]; break;
      case kSub: --n, stack[n - 1] -= stack[n]; break;
      case kMul: --n, stack[n - 1] *= stack[n]; break;
      case kDiv: --n, stack[n - 1] /= stack[n]; break;
      case kPow: --n, stack[n - 1] = std::pow(stack[n - 1], stack[n]); break;
      case kNeg: stack[n - 1] = -stack[n - 1]; break;
      case kSin: stack[n - 1] = std::sin(stack[n - 1]); break;
      case kCos: stack[n - 1] = std::cos(stack[n - 1]); break;
      case kExp: stack[n - 1] = std::exp(stack[n - 1]); break;
      case kSqrt: stack[n - 1] = std::sqrt(stack[n - 1]); break;
    }
  }
  return n == 1 ? stack[0] : std::nan("");
}

bool TimeValue::varies() const {
  if (parts.empty()) return rows.size() > 1;
  for (const Expression &e : parts)
    if (!e.constant()) return true;
  return false;
}

std::vector<double> TimeValue::at(double t) const {
  std::vector<double> v(size());
  if (!parts.empty()) {
    for (size_t k = 0; k < v.size(); ++k) v[k] = parts[k].at(t);
    return v;
  }
  if (rows.empty()) return v;
  // the first row with times[j] > t: t in [times[j-1], times[j])
  const size_t j = static_cast<size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin());
  if (j == 0) return rows.front();
  if (j == times.size()) return rows.back();
  const double s = (t - times[j - 1]) / (times[j] - times[j - 1]);
  for (size_t k = 0; k < v.size(); ++k) v[k] = rows[j - 1][k] + s * (rows[j][k] - rows[j - 1][k]);
  return v;
}

TimeValue TimeValue::of(const std::vector<double> &constant) {
  TimeValue v;
  for (double x : constant) v.parts.emplace_back(x);
  return v;
}

}  // namespace ndcli
