#pragma once
// The style sheet and script of report.html (eval/report_page/viewer.css, viewer.js), embedded
// into the binary at build time (cmake/EmbedText.cmake) so that the page is one self-contained
// file beside its images, and opens from disk with no network.
namespace aamap::report_page {

extern const char* const kStyle;
extern const char* const kScript;

}  // namespace aamap::report_page
