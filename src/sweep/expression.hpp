#pragma once
// Derived sweep values: a small arithmetic expression over other parameters, e.g.
// "3.015 * spacing" or "-sqrt(2 * energy / mass)". Numbers (1, 2.5, 1e-3), parameter names,
// + - * / ^ (power, right-associative), unary minus, parentheses, the constants pi and e and the
// functions sqrt, exp, log (natural), log10, abs, sin, cos, tan, min(a, b), max(a, b).
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

namespace ckpd::sweep {

class ExpressionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Expression {
 public:
  // Throws ExpressionError naming the position of a syntax error.
  explicit Expression(const std::string& text);
  ~Expression();
  Expression(Expression&&) noexcept;
  Expression& operator=(Expression&&) noexcept;

  // The parameter names it reads (constants and functions excluded).
  const std::set<std::string>& names() const { return names_; }
  // Throws ExpressionError for a name missing from `values` or a result that is not finite.
  double evaluate(const std::map<std::string, double>& values) const;
  const std::string& text() const { return text_; }

  struct Node;

 private:
  std::string text_;
  std::unique_ptr<Node> root_;
  std::set<std::string> names_;
};

}  // namespace ckpd::sweep
