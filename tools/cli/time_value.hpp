// Values in time of a scene file (nitschedyn(1), "Values in time"): a load,
// a prescribed motion or an obstacle's position given as constants, as
// expressions in t, or as a table of (t, value) rows, evaluated at t^{n+1}
// before each step. The expression language is small and written here: + -
// * / ^, parentheses, sin cos exp sqrt, pi and t; it is parsed once, into a
// postfix program whose evaluation neither recurses nor allocates.
#ifndef ND_CLI_TIME_VALUE_HPP
#define ND_CLI_TIME_VALUE_HPP

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace ndcli {

// An expression in t, compiled. Throws std::invalid_argument (the message
// names the character where the text goes wrong) for a malformed text.
class Expression {
 public:
  static constexpr size_t kMaxLength = 4096;  // characters of an expression
  static constexpr int kMaxDepth = 64;        // parentheses, calls, signs and powers open at once
  Expression() = default;
  explicit Expression(double constant);
  static Expression parse(std::string_view text);
  double at(double t) const;  // may be NaN or infinite (sqrt(-1), 1/0): the caller checks
  bool constant() const { return constant_; }

  enum Code : unsigned char { kNumber, kT, kAdd, kSub, kMul, kDiv, kPow, kNeg, kSin, kCos, kExp, kSqrt };
  struct Op {
    Code code;
    double x;  // kNumber's value
  };

 private:
  std::vector<Op> ops_;
  int stack_ = 0;  // the most values the evaluation holds at once
  bool constant_ = true;
  friend class ExpressionParser;
};

// A vector value in time: n components, each an expression (a number is a
// constant one), or a table of rows (t, v_1 .. v_n) with increasing t,
// linear between rows and constant outside them.
struct TimeValue {
  std::vector<Expression> parts;           // one per component (empty: the table)
  std::vector<double> times;               // the table's t, increasing
  std::vector<std::vector<double>> rows;   // the table's values, n each
  size_t size() const { return parts.empty() ? (rows.empty() ? 0 : rows[0].size()) : parts.size(); }
  bool empty() const { return size() == 0; }
  bool varies() const;  // false: the same value at every t
  std::vector<double> at(double t) const;
  static TimeValue of(const std::vector<double> &constant);
};

}  // namespace ndcli
#endif
