// report.html: one self-contained page per report folder — the tables of the
// folder's Markdown report and its figures inlined as base64 PNG data URIs (RFC 2397, RFC 4648), no
// script, no stylesheet or font from the network, so that a browser opens it from disk or mail.
#pragma once

#include <string>
#include <vector>

namespace mavloc {

// RFC 4648 section 4 base64 (with '=' padding).
std::string Base64Encode(const std::string& bytes);

// Escapes &, <, >, ", ' for HTML text and attribute values.
std::string HtmlEscape(const std::string& text);

// The subset of Markdown mavloc's reports use (CommonMark names): ATX headings, pipe tables (GitHub
// Flavored Markdown, with ---: alignment), '-'/'*' and '1.' lists, fenced code blocks, block
// quotes, paragraphs; inline code spans, **strong**, *emphasis* and
// [links](url). HTML comments are dropped;
// any other HTML in the text is escaped, not passed through.
std::string MarkdownToHtml(const std::string& markdown);

struct HtmlFigure {
  std::string file;       // PNG file name in the report folder
  std::string caption;    // plain text
  std::string png_bytes;  // the file's contents (inlined as a data URI)
};

struct HtmlPage {
  std::string title;
  std::string markdown;                 // the report's tables and text
  std::vector<HtmlFigure> figures;      // in page order
  std::string figures_note;             // shown instead of figures when there are none
  std::vector<std::string> data_files;  // other files of the folder, listed (relative links)
};

// The whole page: <!DOCTYPE html>, inline CSS, figures after the tables.
std::string RenderReportHtml(const HtmlPage& page);

}  // namespace mavloc
