#include "app/expression.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace sphib::app {

namespace {

class Parser {
 public:
  explicit Parser(const std::string& s) : s_(s) {}

  Number parse() {
    Number v = expr();
    skip();
    if (i_ != s_.size()) fail("unexpected '" + std::string(1, s_[i_]) + "'");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    const std::string shown = s_.size() > 80 ? s_.substr(0, 60) + "..." : s_;
    throw ExpressionError("expression \"" + shown + "\": " + what + " at position " + std::to_string(i_ + 1));
  }
  // Every recursion (a parenthesis, a sign, an exponent) passes through unary(): its depth is bounded,
  // so that deep input is refused instead of overflowing the stack.
  static constexpr int kMaxDepth = 200;
  struct Deeper {
    Parser& p;
    explicit Deeper(Parser& parser) : p(parser) {
      if (++p.depth_ > kMaxDepth) p.fail("nested more than " + std::to_string(kMaxDepth) + " deep (parentheses, signs, powers)");
    }
    ~Deeper() { --p.depth_; }
  };
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool eat(const char* tok) {
    skip();
    const std::string t(tok);
    if (s_.compare(i_, t.size(), t) != 0) return false;
    i_ += t.size();
    return true;
  }

  Number expr() {
    Number a = term();
    while (true) {
      if (eat("+")) a = combine(a, term(), '+');
      else if (eat("-")) a = combine(a, term(), '-');
      else return a;
    }
  }
  Number term() {
    Number a = unary();
    while (true) {
      skip();
      if (s_.compare(i_, 2, "**") == 0) return a;  // handled in power()
      if (eat("*")) a = combine(a, unary(), '*');
      else if (eat("/")) a = combine(a, unary(), '/');
      else return a;
    }
  }
  Number unary() {
    const Deeper guard(*this);
    if (eat("-")) { Number v = unary(); v.value = -v.value; return v; }
    if (eat("+")) return unary();
    return power();
  }
  Number power() {
    Number base = atom();
    if (eat("**")) {
      const Number e = unary();
      Number r{std::pow(base.value, e.value), base.integer && e.integer && e.value >= 0};
      if (!std::isfinite(r.value)) fail("non-finite power");
      return r;
    }
    return base;
  }
  Number atom() {
    skip();
    if (eat("(")) {
      Number v = expr();
      if (!eat(")")) fail("expected ')'");
      return v;
    }
    if (i_ < s_.size() && std::isalpha(static_cast<unsigned char>(s_[i_]))) {
      size_t j = i_;
      while (j < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[j])) || s_[j] == '_')) ++j;
      const std::string name = s_.substr(i_, j - i_);
      if (name == "pi") { i_ = j; return {M_PI, false}; }
      if (name == "sqrt") {
        i_ = j;
        if (!eat("(")) fail("expected '(' after sqrt");
        const Number v = expr();
        if (!eat(")")) fail("expected ')'");
        if (v.value < 0) fail("sqrt of a negative number");
        return {std::sqrt(v.value), false};
      }
      fail("unknown name '" + name + "' (allowed: numbers, + - * / ** ( ), sqrt, pi; {key} for a varied key)");
    }
    if (i_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[i_])) || s_[i_] == '.')) {
      const char* begin = s_.c_str() + i_;
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      const std::string text(begin, static_cast<const char*>(end));
      bool integer = text.find_first_of(".eE") == std::string::npos;
      i_ += text.size();
      return {v, integer};
    }
    if (i_ >= s_.size()) fail("unexpected end");
    fail("unexpected '" + std::string(1, s_[i_]) + "'");
  }
  Number combine(const Number& a, const Number& b, char op) {
    Number r;
    switch (op) {
      case '+': r = {a.value + b.value, a.integer && b.integer}; break;
      case '-': r = {a.value - b.value, a.integer && b.integer}; break;
      case '*': r = {a.value * b.value, a.integer && b.integer}; break;
      default:
        if (b.value == 0.0) fail("division by zero");
        r = {a.value / b.value, false};
    }
    return r;
  }

  const std::string& s_;
  size_t i_ = 0;
  int depth_ = 0;
};

}  // namespace

Number evaluate(const std::string& expression) { return Parser(expression).parse(); }

std::string substitute(const std::string& expression, const std::map<std::string, std::string>& values) {
  std::string out;
  for (size_t i = 0; i < expression.size(); ++i) {
    if (expression[i] != '{') { out += expression[i]; continue; }
    const size_t close = expression.find('}', i);
    if (close == std::string::npos) throw ExpressionError("expression \"" + expression + "\": unclosed '{'");
    const std::string key = expression.substr(i + 1, close - i - 1);
    const auto it = values.find(key);
    if (it == values.end())
      throw ExpressionError("expression \"" + expression + "\": {" + key + "} is not a varied key");
    out += it->second;
    i = close;
  }
  return out;
}

std::string format_number(const Number& n) {
  char buf[64];
  if (n.integer && std::fabs(n.value) < 9.007199254740992e15) {
    std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(n.value));
    return buf;
  }
  for (int p = 1; p <= 17; ++p) {
    std::snprintf(buf, sizeof buf, "%.*g", p, n.value);
    if (std::strtod(buf, nullptr) == n.value) break;
  }
  std::string s(buf);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // 'n': inf/nan left as they are
  return s;
}

}  // namespace sphib::app
