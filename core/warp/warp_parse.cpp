// The warp language's parser (warp_parse.h): recursive descent over the
// grammar there, emitting stack operations as it goes; every bound is
// checked as it is reached, so that hostile text (a million terms, deep
// nesting) ends in one error line, in time linear in its length.
#include "core/warp/warp_parse.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>

#include "core/error.h"

namespace mpvg {

namespace {

struct Function {
  const char* name;
  int arity;
  uint32_t code;
};
constexpr Function kFunctions[] = {
    {"sin", 1, WARP_SIN},     {"cos", 1, WARP_COS},   {"tan", 1, WARP_TAN},     {"atan2", 2, WARP_ATAN2},
    {"sqrt", 1, WARP_SQRT},   {"exp", 1, WARP_EXP},   {"log", 1, WARP_LOG},     {"pow", 2, WARP_POW},
    {"hypot", 2, WARP_HYPOT}, {"min", 2, WARP_MIN},   {"max", 2, WARP_MAX},     {"abs", 1, WARP_ABS},
    {"floor", 1, WARP_FLOOR}, {"clamp", 3, WARP_CLAMP}, {"mix", 3, WARP_MIX},
};

class Parser {
 public:
  explicit Parser(const std::string& text) : s_(text) {}

  WarpProgram program() {
    skip();
    // Bindings: a name followed by '=' (not a function call, not '==').
    for (;;) {
      skip();
      const size_t at = i_;
      std::string name;
      if (!ident(name)) break;
      skip();
      if (peek() != '=') {
        i_ = at;
        break;
      }
      i_++;
      for (const Function& f : kFunctions)
        if (name == f.name) fail(at, "'" + name + "' is a function, not a name to bind");
      if (reserved(name) || find(name) >= 0) fail(at, "'" + name + "' is already defined");
      if (int(names_.size()) >= kWarpSlots) fail(at, "more than " + std::to_string(kWarpSlots) + " names bound");
      expr();
      expect(';', "expected ';' after the binding of '" + name + "'");
      names_.push_back(name);
      emit({WARP_STORE, uint32_t(names_.size() - 1), 0.0}, -1);
    }
    expr();
    expect(';', "expected ';' and the Y expression after the X expression");
    expr();
    skip();
    if (peek() == ';') i_++;
    skip();
    if (i_ < s_.size()) fail(i_, "unexpected '" + std::string(1, s_[i_]) + "' after the Y expression");
    out_.slots = int(names_.size());
    return out_;
  }

 private:
  [[noreturn]] void fail(size_t at, const std::string& what) const {
    throw ParseError("warp expression, column " + std::to_string(at + 1) + ": " + what);
  }
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) i_++;
  }
  void expect(char c, const std::string& what) {
    skip();
    if (peek() != c) fail(i_, what);
    i_++;
  }
  bool ident(std::string& out) {
    if (i_ >= s_.size() || !(std::isalpha(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_')) return false;
    const size_t b = i_;
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_')) i_++;
    out.assign(s_, b, i_ - b);
    return true;
  }
  static bool reserved(const std::string& n) { return n == "x" || n == "y" || n == "w" || n == "h" || n == "pi" || n == "e"; }
  int find(const std::string& n) const {
    for (size_t k = 0; k < names_.size(); k++)
      if (names_[k] == n) return int(k);
    return -1;
  }
  // Appends op; `change` is its effect on the stack's depth.
  void emit(WarpOp op, int change) {
    if (out_.ops.size() >= kWarpMaxOps) fail(i_, "more than " + std::to_string(kWarpMaxOps) + " operations");
    out_.ops.push_back(op);
    depth_ += change;
    if (depth_ > kWarpStack) fail(i_, "more than " + std::to_string(kWarpStack) + " values pending at once");
    if (depth_ > out_.stack) out_.stack = depth_;
  }
  struct Nest {
    Parser& p;
    Nest(Parser& parser, size_t at) : p(parser) {
      if (++p.nesting_ > kWarpMaxNesting) p.fail(at, "nested deeper than " + std::to_string(kWarpMaxNesting) + " levels");
    }
    ~Nest() { p.nesting_--; }
  };

  void expr() {
    Nest n(*this, i_);
    left_to_right('+', WARP_ADD, '-', WARP_SUB, &Parser::term);
  }
  void term() { left_to_right('*', WARP_MUL, '/', WARP_DIV, &Parser::unary); }
  // operand { (a | b) operand }, applied left to right.
  void left_to_right(char a, uint32_t code_a, char b, uint32_t code_b, void (Parser::*operand)()) {
    (this->*operand)();
    for (;;) {
      skip();
      const char c = peek();
      if (c != a && c != b) return;
      i_++;
      (this->*operand)();
      emit({c == a ? code_a : code_b, 0, 0.0}, -1);
    }
  }
  void unary() {
    Nest n(*this, i_);
    skip();
    if (peek() == '-' || peek() == '+') {
      const bool neg = peek() == '-';
      i_++;
      unary();
      if (neg) emit({WARP_NEG, 0, 0.0}, 0);
      return;
    }
    primary();
    skip();
    if (peek() == '^') {
      i_++;
      unary();
      emit({WARP_POW, 0, 0.0}, -1);
    }
  }
  void primary() {
    skip();
    const size_t at = i_;
    const char c = peek();
    if (c == '(') {
      i_++;
      expr();
      expect(')', "expected ')' to close the '(' at column " + std::to_string(at + 1));
      return;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    std::string name;
    if (!ident(name)) {
      if (c == '\0') fail(at, "expected a value, found the end of the text");
      fail(at, "expected a value, found '" + std::string(1, c) + "'");
    }
    skip();
    if (peek() == '(') {
      for (const Function& f : kFunctions) {
        if (name != f.name) continue;
        i_++;
        for (int a = 0; a < f.arity; a++) {
          if (a > 0) expect(',', "'" + name + "' takes " + std::to_string(f.arity) + " arguments");
          expr();
        }
        expect(')', "'" + name + "' takes " + std::to_string(f.arity) + (f.arity == 1 ? " argument" : " arguments"));
        emit({f.code, 0, 0.0}, 1 - f.arity);
        return;
      }
      fail(at, "unknown function '" + name + "'");
    }
    if (name == "x") return emit({WARP_X, 0, 0.0}, 1);
    if (name == "y") return emit({WARP_Y, 0, 0.0}, 1);
    if (name == "w") return emit({WARP_W, 0, 0.0}, 1);
    if (name == "h") return emit({WARP_H, 0, 0.0}, 1);
    if (name == "pi") return emit({WARP_CONST, 0, 3.14159265358979323846}, 1);
    if (name == "e") return emit({WARP_CONST, 0, 2.71828182845904523536}, 1);
    const int k = find(name);
    if (k < 0) fail(at, "unknown name '" + name + "'");
    emit({WARP_LOAD, uint32_t(k), 0.0}, 1);
  }
  void number() {
    const size_t at = i_;
    // digits [. digits] [e [+-] digits], at most 64 characters.
    size_t j = i_;
    while (j < s_.size() && std::isdigit(static_cast<unsigned char>(s_[j]))) j++;
    if (j < s_.size() && s_[j] == '.') {
      j++;
      while (j < s_.size() && std::isdigit(static_cast<unsigned char>(s_[j]))) j++;
    }
    if (j < s_.size() && (s_[j] == 'e' || s_[j] == 'E')) {
      size_t k = j + 1;
      if (k < s_.size() && (s_[k] == '+' || s_[k] == '-')) k++;
      if (k < s_.size() && std::isdigit(static_cast<unsigned char>(s_[k]))) {
        j = k;
        while (j < s_.size() && std::isdigit(static_cast<unsigned char>(s_[j]))) j++;
      }
    }
    if (j - at > 64) fail(at, "a number longer than 64 characters");
    double v = 0.0;
    const auto r = std::from_chars(s_.data() + at, s_.data() + j, v);
    if (r.ec != std::errc() || r.ptr != s_.data() + j || !std::isfinite(v))
      fail(at, "'" + s_.substr(at, j - at) + "' is not a finite number");
    i_ = j;
    emit({WARP_CONST, 0, v}, 1);
  }

  const std::string& s_;
  size_t i_ = 0;
  int depth_ = 0, nesting_ = 0;
  std::vector<std::string> names_;
  WarpProgram out_;
};

}  // namespace

WarpProgram parse_warp_expression(const std::string& text) { return Parser(text).program(); }

}  // namespace mpvg
