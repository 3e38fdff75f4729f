#pragma once
// The arithmetic of `sphib sweep --derive key=EXPR`: {key} substitution and a small
// recursive-descent evaluator with Python's number semantics (what scripts/sweep.py evaluates).
//
//   expr   := term (('+' | '-') term)*
//   term   := unary (('*' | '/') unary)*
//   unary  := ('+' | '-') unary | power
//   power  := atom ('**' unary)?          right-associative, binds tighter than unary minus on its left
//   atom   := number | 'pi' | 'sqrt' '(' expr ')' | '(' expr ')'
//
// Integers stay integers under + - * and ** (non-negative integer exponent); '/' and sqrt give
// floats, as in Python 3, so `{grid.nx}` derives an integer key and `0.1*3/{grid.nx}` a float.
#include <map>
#include <stdexcept>
#include <string>

namespace sphib::app {

struct ExpressionError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct Number {
  double value = 0.0;
  bool integer = false;
};

// Evaluates the expression; throws ExpressionError naming the position of the first problem.
Number evaluate(const std::string& expression);

// Replaces every {key} by values.at(key); throws ExpressionError for a key not in values.
std::string substitute(const std::string& expression, const std::map<std::string, std::string>& values);

// As Python's str/repr: an integer without a point ("40"); a float by the shortest digits that
// read back to the same double, always with '.' or an exponent ("0.0075", "2.0", "1e-05").
std::string format_number(const Number& n);

}  // namespace sphib::app
