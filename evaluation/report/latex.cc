#include "evaluation/report/latex.h"

namespace mavloc {

std::string LatexEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    if (c == '\\')
      out += "\\textbackslash{}";
    else if (c == '~')
      out += "\\textasciitilde{}";
    else if (c == '^')
      out += "\\textasciicircum{}";
    else if (c == '_' || c == '%' || c == '&' || c == '#' || c == '$' || c == '{' || c == '}')
      out += std::string("\\") + c;
    else
      out.push_back(c);
  }
  return out;
}

}  // namespace mavloc
