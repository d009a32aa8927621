#include "src/sweep/expression.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace ckpd::sweep {

// A parsed expression: a number, a name, a unary or binary operator, or a function call.
struct Expression::Node {
  char op = 0;  // 'n' number, 'v' variable, 'f' function, '~' negate, or + - * / ^
  double number = 0;
  std::string name;
  std::vector<std::unique_ptr<Node>> args;
};

namespace {

using Node = Expression::Node;

// Recursive descent: sum := product (('+'|'-') product)*; product := unary (('*'|'/') unary)*;
// unary := '-' unary | '+' unary | power; power := atom ('^' unary)?; atom := number | name |
// name '(' sum (',' sum)* ')' | '(' sum ')'. `-2^2` is -4 as in mathematics.
// Nesting (parentheses, unary signs, powers, calls) is bounded by kMaxDepth and the length by
// kMaxLength, so that neither the parser nor eval() can exhaust the stack: a sum of N terms is
// a left-leaning tree N deep, and eval() recurses along it.
constexpr std::size_t kMaxDepth = 200;
constexpr std::size_t kMaxLength = 4096;
constexpr std::size_t kMaxNodes = 1000;

class Parser {
 public:
  Parser(const std::string& text, std::set<std::string>& names) : text_(text), names_(names) {}

  std::unique_ptr<Node> parse() {
    if (text_.size() > kMaxLength)
      throw ExpressionError("expression of " + std::to_string(text_.size()) +
                            " characters: longer than the limit of " + std::to_string(kMaxLength));
    auto root = sum();
    skip();
    if (pos_ != text_.size()) fail("an operator or the end of the expression");
    return root;
  }

 private:
  [[noreturn]] void fail(const std::string& expected) const {
    // A long expression is shown by its start only (the error names the position).
    const std::string shown = text_.size() > 60 ? text_.substr(0, 57) + "..." : text_;
    throw ExpressionError("expression '" + shown + "': at character " + std::to_string(pos_ + 1) +
                          ": expected " + expected);
  }
  void skip() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  // Entered on every nesting level (a parenthesis, a sign, a power, a call's argument).
  struct Level {
    Parser& p;
    explicit Level(Parser& parser) : p(parser) {
      if (++p.depth_ > kMaxDepth) p.fail("at most " + std::to_string(kMaxDepth) + " nested levels");
    }
    ~Level() { --p.depth_; }
  };
  std::unique_ptr<Node> node() {
    if (++nodes_ > kMaxNodes)
      fail("at most " + std::to_string(kMaxNodes) + " numbers, names and operators in all");
    return std::make_unique<Node>();
  }
  std::unique_ptr<Node> binary(char op, std::unique_ptr<Node> a, std::unique_ptr<Node> b) {
    auto n = node();
    n->op = op;
    n->args.push_back(std::move(a));
    n->args.push_back(std::move(b));
    return n;
  }
  std::unique_ptr<Node> sum() {
    auto left = product();
    for (;;) {
      if (accept('+'))
        left = binary('+', std::move(left), product());
      else if (accept('-'))
        left = binary('-', std::move(left), product());
      else
        return left;
    }
  }
  std::unique_ptr<Node> product() {
    auto left = unary();
    for (;;) {
      if (accept('*'))
        left = binary('*', std::move(left), unary());
      else if (accept('/'))
        left = binary('/', std::move(left), unary());
      else
        return left;
    }
  }
  std::unique_ptr<Node> unary() {
    const Level level(*this);
    if (accept('-')) {
      auto n = node();
      n->op = '~';
      n->args.push_back(unary());
      return n;
    }
    if (accept('+')) return unary();
    auto base = atom();
    if (accept('^')) return binary('^', std::move(base), unary());
    return base;
  }
  std::unique_ptr<Node> atom() {
    skip();
    if (pos_ >= text_.size()) fail("a number, a name or '('");
    auto n = node();
    const char c = text_[pos_];
    if (c == '(') {
      ++pos_;
      n = sum();
      if (!accept(')')) fail("')'");
      return n;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const char* begin = text_.c_str() + pos_;
      char* end = nullptr;
      n->op = 'n';
      n->number = std::strtod(begin, &end);
      if (end == begin) fail("a number");
      pos_ += static_cast<std::size_t>(end - begin);
      return n;
    }
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const std::size_t start = pos_;
      while (pos_ < text_.size() &&
             (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_'))
        ++pos_;
      n->name = text_.substr(start, pos_ - start);
      if (accept('(')) {
        static const std::set<std::string> one{"sqrt", "exp", "log", "log10",
                                               "abs",  "sin", "cos", "tan"};
        static const std::set<std::string> two{"min", "max"};
        const std::size_t at = start;
        n->op = 'f';
        n->args.push_back(sum());
        while (accept(',')) n->args.push_back(sum());
        if (!accept(')')) fail("')' closing " + n->name + "(");
        const std::size_t want = one.count(n->name) ? 1 : two.count(n->name) ? 2 : 0;
        if (want == 0) {
          pos_ = at;
          fail("a known function (sqrt, exp, log, log10, abs, sin, cos, tan, min, max), not '" +
               n->name + "'");
        }
        if (n->args.size() != want) {
          pos_ = at;
          fail(n->name + " with " + std::to_string(want) + " argument(s)");
        }
        return n;
      }
      if (n->name == "pi" || n->name == "e") {
        n->op = 'n';
        n->number = n->name == "pi" ? M_PI : M_E;
        return n;
      }
      n->op = 'v';
      names_.insert(n->name);
      return n;
    }
    fail("a number, a name or '('");
  }

  const std::string& text_;
  std::set<std::string>& names_;
  std::size_t pos_ = 0;
  std::size_t depth_ = 0;
  std::size_t nodes_ = 0;
};

double eval(const Node& n, const std::map<std::string, double>& values, const std::string& text) {
  auto arg = [&](std::size_t i) { return eval(*n.args[i], values, text); };
  switch (n.op) {
    case 'n':
      return n.number;
    case 'v': {
      const auto it = values.find(n.name);
      if (it == values.end())
        throw ExpressionError("expression '" + text + "': '" + n.name +
                              "' is not a numeric parameter");
      return it->second;
    }
    case '~':
      return -arg(0);
    case '+':
      return arg(0) + arg(1);
    case '-':
      return arg(0) - arg(1);
    case '*':
      return arg(0) * arg(1);
    case '/':
      return arg(0) / arg(1);
    case '^':
      return std::pow(arg(0), arg(1));
    default:
      break;
  }
  const double a = arg(0);
  if (n.name == "sqrt") return std::sqrt(a);
  if (n.name == "exp") return std::exp(a);
  if (n.name == "log") return std::log(a);
  if (n.name == "log10") return std::log10(a);
  if (n.name == "abs") return std::abs(a);
  if (n.name == "sin") return std::sin(a);
  if (n.name == "cos") return std::cos(a);
  if (n.name == "tan") return std::tan(a);
  if (n.name == "min") return std::min(a, arg(1));
  return std::max(a, arg(1));  // the parser admits no other function
}

}  // namespace

Expression::Expression(const std::string& text) : text_(text) {
  root_ = Parser(text_, names_).parse();
}
Expression::~Expression() = default;
Expression::Expression(Expression&&) noexcept = default;
Expression& Expression::operator=(Expression&&) noexcept = default;

double Expression::evaluate(const std::map<std::string, double>& values) const {
  const double v = eval(*root_, values, text_);
  if (!std::isfinite(v))
    throw ExpressionError("expression '" + text_ + "' evaluates to " + std::to_string(v) +
                          " (not a finite number)");
  return v;
}

}  // namespace ckpd::sweep
