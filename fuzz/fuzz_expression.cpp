// libFuzzer harness: the sweep expression parser and evaluator (src/sweep/expression.cpp).
// Any input must either parse or throw ExpressionError; evaluation with every name bound must
// either give a finite number or throw ExpressionError. Anything else (a crash, a sanitizer
// report, another exception) is a finding.
#include <cstdint>
#include <map>
#include <string>

#include "src/sweep/expression.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const ckpd::sweep::Expression e(text);
    std::map<std::string, double> values;
    double x = 0.5;
    for (const std::string& name : e.names()) values[name] = (x *= 3.0);
    try {
      e.evaluate(values);
    } catch (const ckpd::sweep::ExpressionError&) {
    }
  } catch (const ckpd::sweep::ExpressionError&) {
  }
  return 0;
}
