#include "evaluation/report_html.h"
#include "core/text.h"

#include <cctype>
#include <sstream>

namespace mavloc {
namespace {

bool StartsWith(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

// Inline Markdown: `code`, **strong**, *emphasis*, [text](url); everything else escaped.
std::string Inline(const std::string& raw) {
  std::string out;
  size_t i = 0;
  bool strong = false;
  while (i < raw.size()) {
    if (raw[i] == '`') {
      const auto end = raw.find('`', i + 1);
      if (end != std::string::npos) {
        out += "<code>" + HtmlEscape(raw.substr(i + 1, end - i - 1)) + "</code>";
        i = end + 1;
        continue;
      }
    }
    if (raw.compare(i, 2, "**") == 0) {
      // Open only when a closing ** follows, so that a lone "**" stays text.
      if (strong || raw.find("**", i + 2) != std::string::npos) {
        out += strong ? "</strong>" : "<strong>";
        strong = !strong;
        i += 2;
        continue;
      }
    }
    // *emphasis*: an opening star followed by a non-blank, a closing one after a non-blank.
    if (raw[i] == '*' && i + 1 < raw.size() && raw[i + 1] != '*' && raw[i + 1] != ' ') {
      const auto end = raw.find('*', i + 1);
      if (end != std::string::npos && raw[end - 1] != ' ' &&
          (end + 1 >= raw.size() || raw[end + 1] != '*') && raw.find('\n', i) > end) {
        out += "<em>" + Inline(raw.substr(i + 1, end - i - 1)) + "</em>";
        i = end + 1;
        continue;
      }
    }
    if (raw[i] == '[') {
      const auto close = raw.find("](", i + 1);
      const auto end = close == std::string::npos ? close : raw.find(')', close + 2);
      if (close != std::string::npos && end != std::string::npos && raw.find('\n', i) > end) {
        const std::string url = raw.substr(close + 2, end - close - 2);
        // No javascript: or other schemes: relative links and http(s) only.
        const bool safe = url.find(':') == std::string::npos || StartsWith(url, "http://") ||
                          StartsWith(url, "https://");
        if (safe) {
          out += "<a href=\"" + HtmlEscape(url) + "\">" + Inline(raw.substr(i + 1, close - i - 1)) +
                 "</a>";
          i = end + 1;
          continue;
        }
      }
    }
    out += HtmlEscape(std::string(1, raw[i]));
    ++i;
  }
  if (strong) out += "</strong>";
  return out;
}

std::vector<std::string> SplitTableRow(const std::string& line) {
  std::string row = Trim(line);
  if (!row.empty() && row.front() == '|') row.erase(0, 1);
  if (!row.empty() && row.back() == '|') row.pop_back();
  std::vector<std::string> cells;
  std::string cell;
  bool in_code = false;
  for (size_t i = 0; i < row.size(); ++i) {
    const char c = row[i];
    if (c == '`') in_code = !in_code;
    if (c == '\\' && i + 1 < row.size() && row[i + 1] == '|') {
      cell += '|';
      ++i;
    } else if (c == '|' && !in_code) {
      cells.push_back(Trim(cell));
      cell.clear();
    } else {
      cell += c;
    }
  }
  cells.push_back(Trim(cell));
  return cells;
}

bool IsSeparatorRow(const std::string& line) {
  const auto cells = SplitTableRow(line);
  for (const auto& cell : cells) {
    if (cell.empty() || cell.find_first_not_of(":-") != std::string::npos ||
        cell.find('-') == std::string::npos)
      return false;
  }
  return !cells.empty();
}

std::string TableHtml(const std::vector<std::string>& lines) {
  std::vector<std::string> align;
  const bool has_header = lines.size() >= 2 && IsSeparatorRow(lines[1]);
  if (has_header) {
    for (const auto& cell : SplitTableRow(lines[1]))
      align.push_back(cell.back() == ':' ? (cell.front() == ':' ? "center" : "right") : "");
  }
  std::string html = "<table>\n";
  for (size_t r = 0; r < lines.size(); ++r) {
    if (has_header && r == 1) continue;
    const bool head = has_header && r == 0;
    const auto cells = SplitTableRow(lines[r]);
    html += "<tr>";
    for (size_t c = 0; c < cells.size(); ++c) {
      const std::string tag = head ? "th" : "td";
      const std::string style =
          c < align.size() && !align[c].empty() ? " style=\"text-align:" + align[c] + "\"" : "";
      html += "<" + tag + style + ">" + Inline(cells[c]) + "</" + tag + ">";
    }
    html += "</tr>\n";
  }
  return html + "</table>\n";
}

// Drops <!-- ... --> comments (they may span lines).
std::string StripComments(const std::string& text) {
  std::string out;
  size_t i = 0;
  while (i < text.size()) {
    const auto begin = text.find("<!--", i);
    if (begin == std::string::npos) {
      out += text.substr(i);
      break;
    }
    out += text.substr(i, begin - i);
    const auto end = text.find("-->", begin + 4);
    if (end == std::string::npos) break;
    i = end + 3;
  }
  return out;
}

bool IsOrderedItem(const std::string& line, std::string* rest) {
  size_t i = 0;
  while (i < line.size() && std::isdigit(static_cast<unsigned char>(line[i]))) ++i;
  if (i == 0 || i + 1 >= line.size() || line[i] != '.' || line[i + 1] != ' ') return false;
  *rest = line.substr(i + 2);
  return true;
}

// RFC 3986 percent-encoding of a relative file name (unreserved characters kept).
std::string PercentEncode(const std::string& name) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '-' || c == '.' || c == '_' || c == '~') {
      out += c;
    } else {
      out += '%';
      out += kHex[u >> 4];
      out += kHex[u & 15];
    }
  }
  return out;
}

}  // namespace

std::string Base64Encode(const std::string& bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (static_cast<uint8_t>(bytes[i]) << 16) |
                       (static_cast<uint8_t>(bytes[i + 1]) << 8) |
                       static_cast<uint8_t>(bytes[i + 2]);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const uint32_t v = static_cast<uint8_t>(bytes[i]) << 16;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const uint32_t v =
        (static_cast<uint8_t>(bytes[i]) << 16) | (static_cast<uint8_t>(bytes[i + 1]) << 8);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

std::string HtmlEscape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string MarkdownToHtml(const std::string& markdown) {
  std::vector<std::string> lines;
  {
    std::istringstream in(StripComments(markdown));
    std::string line;
    while (std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines.push_back(line);
    }
  }
  std::string html;
  std::string paragraph;
  const auto flush_paragraph = [&] {
    if (!Trim(paragraph).empty()) html += "<p>" + Inline(Trim(paragraph)) + "</p>\n";
    paragraph.clear();
  };
  size_t i = 0;
  while (i < lines.size()) {
    const std::string line = lines[i];
    const std::string trimmed = Trim(line);
    if (trimmed.empty()) {
      flush_paragraph();
      ++i;
      continue;
    }
    if (StartsWith(trimmed, "```")) {
      flush_paragraph();
      std::string code;
      ++i;
      while (i < lines.size() && !StartsWith(Trim(lines[i]), "```")) code += lines[i++] + "\n";
      ++i;  // the closing fence
      html += "<pre><code>" + HtmlEscape(code) + "</code></pre>\n";
      continue;
    }
    if (trimmed.front() == '#') {
      size_t level = 0;
      while (level < trimmed.size() && trimmed[level] == '#') ++level;
      if (level <= 6 && level < trimmed.size() && trimmed[level] == ' ') {
        flush_paragraph();
        const std::string n = std::to_string(level);
        html += "<h" + n + ">" + Inline(Trim(trimmed.substr(level))) + "</h" + n + ">\n";
        ++i;
        continue;
      }
    }
    if (trimmed.front() == '|') {
      flush_paragraph();
      std::vector<std::string> table;
      while (i < lines.size() && !Trim(lines[i]).empty() && Trim(lines[i]).front() == '|')
        table.push_back(lines[i++]);
      html += TableHtml(table);
      continue;
    }
    if (trimmed.front() == '>') {
      flush_paragraph();
      std::string quote;
      while (i < lines.size() && !Trim(lines[i]).empty() && Trim(lines[i]).front() == '>')
        quote += Trim(Trim(lines[i++]).substr(1)) + "\n";
      html += "<blockquote>" + Inline(Trim(quote)) + "</blockquote>\n";
      continue;
    }
    std::string rest;
    const bool bullet = StartsWith(trimmed, "- ") || StartsWith(trimmed, "* ");
    if (bullet || IsOrderedItem(trimmed, &rest)) {
      flush_paragraph();
      const std::string tag = bullet ? "ul" : "ol";
      html += "<" + tag + ">\n";
      std::string item;
      const auto flush_item = [&] {
        if (!item.empty()) html += "<li>" + Inline(Trim(item)) + "</li>\n";
        item.clear();
      };
      while (i < lines.size()) {
        const std::string t = Trim(lines[i]);
        std::string r;
        if (bullet ? (StartsWith(t, "- ") || StartsWith(t, "* ")) : IsOrderedItem(t, &r)) {
          flush_item();
          item = bullet ? t.substr(2) : r;
        } else if (!t.empty() && (lines[i].front() == ' ' || lines[i].front() == '\t')) {
          item += " " + t;  // continuation line of the item
        } else {
          break;
        }
        ++i;
      }
      flush_item();
      html += "</" + tag + ">\n";
      continue;
    }
    paragraph += line + "\n";
    ++i;
  }
  flush_paragraph();
  return html;
}

std::string RenderReportHtml(const HtmlPage& page) {
  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
      "<meta name=\"generator\" content=\"mavloc\">\n<title>" +
      HtmlEscape(page.title) +
      "</title>\n<style>\n"
      "body{font-family:sans-serif;margin:1.5em auto;max-width:75em;padding:0 1em;color:#222;"
      "line-height:1.45}\n"
      "table{border-collapse:collapse;margin:0.8em 0;font-size:0.9em;display:block;"
      "overflow-x:auto}\n"
      "th,td{border:1px solid #ccc;padding:0.25em 0.5em}th{background:#f0f0f0}"
      "tr:nth-child(even) td{background:#fafafa}\n"
      "code{background:#f3f3f3;padding:0 0.2em}pre{background:#f6f6f6;padding:0.6em;"
      "overflow-x:auto}\n"
      "figure{margin:1.2em 0}figure img{max-width:100%;height:auto;border:1px solid #ddd}\n"
      "figcaption{font-size:0.9em;color:#444}\n"
      ".note{border-left:4px solid #d9822b;background:#fff6ec;padding:0.6em 1em}\n"
      "</style>\n</head>\n<body>\n";
  html += MarkdownToHtml(page.markdown);
  html += "<h2 id=\"figures\">Figures</h2>\n";
  if (page.figures.empty()) {
    html +=
        "<div class=\"note\" id=\"figures-note\">" + MarkdownToHtml(page.figures_note) + "</div>\n";
  }
  for (const auto& figure : page.figures) {
    html += "<figure id=\"" + HtmlEscape(figure.file) + "\">\n<img alt=\"" +
            HtmlEscape(figure.file) + "\" src=\"data:image/png;base64," +
            Base64Encode(figure.png_bytes) + "\">\n<figcaption><code>" + HtmlEscape(figure.file) +
            "</code>: " + HtmlEscape(figure.caption) + "</figcaption>\n</figure>\n";
  }
  if (!page.data_files.empty()) {
    html += "<h2>Files in this folder</h2>\n<ul>\n";
    for (const auto& file : page.data_files)
      html += "<li><a href=\"" + PercentEncode(file) + "\">" + HtmlEscape(file) + "</a></li>\n";
    html += "</ul>\n";
  }
  return html + "</body>\n</html>\n";
}

}  // namespace mavloc
