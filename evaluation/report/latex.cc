#include "evaluation/report/latex.h"

namespace mavloc {

std::string LatexEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    if (c == '_' || c == '%' || c == '&' || c == '#' || c == '$' || c == '{' || c == '}')
      out.push_back('\\');
    out.push_back(c);
  }
  return out;
}

}  // namespace mavloc
