#pragma once
// The page a robotics engineer reads after `proprio learn` (issue 21): one self-contained offline
// HTML file (inline SVG charts, images beside it, no server, no network, no external JS/CSS) made
// from a learn run directory alone (docs/report.md; the layout it reads is the run directory of
// loop::run_learn: learn.json, decisions.jsonl, pushes/push_NNN/*.png, and optionally table.png,
// vocabulary.vocab, lda.model, model.mot and words/). The library call behind `proprio report`.

#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/core/provenance.hpp"

namespace proprio::loop {

inline constexpr const char* kLearnReportFormat = "proprio.learn_report";

/// The ids of the page's sections, in page order (docs/report.md says what each shows).
inline constexpr std::array<std::string_view, 10> kLearnReportSections{
    "summary", "table",  "pushes",   "segmentation", "words",
    "topics",  "models", "held-out", "timing",       "decisions"};

/// decisions.jsonl is read up to this many bytes (the rest is counted, not shown).
inline constexpr std::size_t kMaxDecisionBytes = std::size_t{16} << 20;
/// A decisions.jsonl line longer than this is skipped (and counted) unread.
inline constexpr std::size_t kMaxDecisionLineBytes = std::size_t{64} << 10;
/// learn.json is refused above this size.
inline constexpr std::uintmax_t kMaxLearnJsonBytes = std::uintmax_t{64} << 20;

struct LearnReportOptions {
  std::filesystem::path dir;  ///< the run directory (proprio learn --out); required
  /// The page; empty: dir/report.html. Its images go into the directory beside it named as the
  /// page without its extension (dir/report/ for the default).
  std::filesystem::path out;
  bool overwrite = false;   ///< replace an existing page (and its image directory)
  int top_words = 10;       ///< the most probable words drawn per topic
  int max_pushes = 200;     ///< pushes drawn at most (the rest are listed in the table only)
  int max_decisions = 300;  ///< decisions listed in full at most (all are counted)

  /// Throws Error naming the first bad option (an empty dir, a bound).
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.dir, {"dir", "The run directory of proprio learn"});
    v(self.out, {"out", "The page to write (default DIR/report.html; images beside it)"});
    v(self.overwrite, {"overwrite", "Replace an existing page and its image directory"});
    v(self.top_words, {"top_words", "Words drawn per topic", core::between(1, 50)});
    v(self.max_pushes, {"max_pushes", "Pushes drawn at most", core::between(1, 1000)});
    v(self.max_decisions,
      {"max_decisions", "Decisions listed in full at most", core::between(0, 100000)});
  }
};

struct LearnReportSummary {
  std::filesystem::path page;     ///< the HTML page written
  std::filesystem::path images;   ///< the directory of its images
  bool complete = false;          ///< learn.json said the run was complete (and no INCOMPLETE)
  int pushes = 0;                 ///< pushes in learn.json
  int pushes_drawn = 0;           ///< executed pushes whose images were drawn
  int image_files = 0;            ///< images written beside the page
  int classes = 0;                ///< learned classes (learn.json "objects")
  int decisions = 0;              ///< decisions.jsonl lines read
  double mot_accuracy = -1;       ///< held-out MoT accuracy, [0, 1]; -1: not recorded
  double argmax_accuracy = -1;    ///< held-out argmax accuracy; -1: not recorded
  double headline_accuracy = -1;  ///< learn.json's "headline" accuracy; -1: not recorded
  std::size_t page_bytes = 0;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.page, {"page", "The HTML page written"});
    v(self.images, {"images", "The directory of its images"});
    v(self.complete, {"complete", "learn.json said the run was complete"});
    v(self.pushes, {"pushes", "Pushes in learn.json"});
    v(self.pushes_drawn, {"pushes_drawn", "Executed pushes whose images were drawn"});
    v(self.image_files, {"image_files", "Images written beside the page"});
    v(self.classes, {"classes", "Learned classes"});
    v(self.decisions, {"decisions", "Decision log lines read"});
    v(self.mot_accuracy, {"mot_accuracy", "Held-out Mixture of Topics accuracy; -1: none"});
    v(self.argmax_accuracy, {"argmax_accuracy", "Held-out argmax theta accuracy; -1: none"});
    v(self.headline_accuracy,
      {"headline_accuracy", "Held-out accuracy of learn's headline figure; -1: none"});
    v(self.page_bytes, {"page_bytes", "Size of the page, bytes"});
  }
};

// NOLINTNEXTLINE(bugprone-exception-escape)
struct LearnReportResult {
  LearnReportOptions options;
  LearnReportSummary summary;
  /// format "proprio.learn_report" (docs/formats/schemas/learn_report.schema.json): provenance,
  /// options and summary; also written as the image directory's summary.json.
  core::Json document;
  std::string message;  ///< one line: what happened (brief()'s first line)
  [[nodiscard]] std::string brief() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.options, {"options", "The report's options"});
    v(self.summary, {"summary", "What was written"});
  }
};

/// Every file and directory of the run directory `dir` the report reads (learn.json,
/// decisions.jsonl, table.png, words/, the model files, each listed push's images): the outputs
/// (the page, its image directory, a CLI's --json) must be none of them. Reads learn.json; throws
/// as write_learn_report does when it is bad.
std::vector<std::filesystem::path> learn_report_inputs(const std::filesystem::path& dir);

/// Reads a decision log (DIR/decisions.jsonl) as write_learn_report does: its first
/// kMaxDecisionBytes, lines over kMaxDecisionLineBytes skipped; returns the decisions (lines
/// that are JSON objects). Throws Error naming the line of one that is not.
int count_learn_decisions(const std::filesystem::path& file);

/// The page write_learn_report writes for `options` and the directory of its images.
std::filesystem::path learn_report_page(const LearnReportOptions& options);
std::filesystem::path learn_report_images(const LearnReportOptions& options);

/// Reads the run directory options.dir and writes the page (atomically: its images are staged and
/// swapped in first, then the page is renamed into place) with every section of
/// kLearnReportSections. Missing optional items are said "not recorded" on the page; an optional
/// file present but unreadable is shown with its problem. Throws Error naming the file when
/// learn.json is missing, not format "proprio.learn" version 1 or lacks a required member,
/// decisions.jsonl is missing or has a line that is no JSON object, or an executed push lacks one
/// of its images; Error when the page exists (without overwrite) or would replace an input.
LearnReportResult write_learn_report(
    const LearnReportOptions& options,
    const core::Provenance& provenance = core::Provenance::current({}));

}  // namespace proprio::loop
