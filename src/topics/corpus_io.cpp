#include "proprio/topics/corpus_io.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <unordered_set>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::topics {
namespace fs = std::filesystem;

namespace {

// Walks a text buffer line by line (LF or CRLF), counting lines from 1.
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}

  // Next line without its terminator; false at the end.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = text_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line = text_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = stop == text_.size() ? stop : stop + 1;
    ++number_;
    return true;
  }
  [[nodiscard]] long number() const { return number_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  long number_ = 0;
};

// Reads a file line by line without holding it (sharded reading: every rank parses the whole file
// and keeps only its documents), with a checksum (FNV-1a, 64 bits) of the lines read.
class StreamLines {
 public:
  explicit StreamLines(const fs::path& path) : in_(path, std::ios::binary) {
    if (!in_) throw Error::in_file(path, "cannot open");
  }
  bool next(std::string_view& line) {
    if (!std::getline(in_, buffer_)) return false;
    for (const char c : buffer_) hash_ = (hash_ ^ static_cast<unsigned char>(c)) * kPrime;
    hash_ = (hash_ ^ static_cast<unsigned char>('\n')) * kPrime;
    line = buffer_;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++number_;
    return true;
  }
  [[nodiscard]] long number() const { return number_; }
  [[nodiscard]] std::uint64_t checksum() const { return hash_; }

 private:
  static constexpr std::uint64_t kPrime = 1099511628211ULL;
  std::ifstream in_;
  std::string buffer_;
  long number_ = 0;
  std::uint64_t hash_ = 14695981039346656037ULL;
};

bool is_blank(std::string_view s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return c == ' ' || c == '\t'; });
}

// Splits on spaces and tabs.
std::vector<std::string_view> fields(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    if (i == s.size()) break;
    std::size_t j = i;
    while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
    out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

// A whole field as a (signed) integer, or false.
bool to_int64(std::string_view s, std::int64_t& v) {
  if (s.empty()) return false;
  const char* b = s.data();
  if (*b == '+') ++b;
  const auto r = std::from_chars(b, s.data() + s.size(), v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

std::string quote(std::string_view s) {
  std::string out = "'";
  out.append(s.substr(0, 40));
  if (s.size() > 40) out += "...";
  out += "'";
  return out;
}

std::int64_t integer_field(const fs::path& file, long line, std::string_view field,
                           const char* what) {
  std::int64_t v = 0;
  if (!to_int64(field, v)) {
    std::string msg = what;
    msg += " is not an integer: ";
    msg += quote(field);
    throw Error::at_line(file, line, msg);
  }
  return v;
}

struct Entry {
  std::int64_t doc;
  std::int32_t word;
  std::int32_t count;
  long line;
};

// What a format calls an entry's fields and its header's entry count, in errors.
struct EntryNames {
  const char* document;  // "docID"
  const char* word;      // "wordID"
  const char* too_many;  // "more entries than the header's NNZ = "
};

// Checks the entry (d, w, c) of line `ln` (1-based ids) against the header's sizes and appends it.
void add_entry(std::vector<Entry>& entries, const fs::path& file, long ln, std::int64_t d,
               std::int64_t w, std::int64_t c, std::int64_t num_docs, std::int64_t num_words,
               std::int64_t nnz, const EntryNames& names) {
  auto outside = [&](const char* name, std::int64_t v, std::int64_t n) {
    std::string msg = name;
    msg += " " + std::to_string(v);
    msg += " outside [1, " + std::to_string(n) + "]";
    return Error::at_line(file, ln, msg);
  };
  if (d < 1 || d > num_docs) throw outside(names.document, d, num_docs);
  if (w < 1 || w > num_words) throw outside(names.word, w, num_words);
  if (c <= 0 || c > std::numeric_limits<std::int32_t>::max()) {
    throw Error::at_line(file, ln, "count " + std::to_string(c) + " is not positive");
  }
  if (static_cast<std::int64_t>(entries.size()) == nnz) {
    throw Error::at_line(file, ln, names.too_many + std::to_string(nnz));
  }
  entries.push_back({d - 1, static_cast<std::int32_t>(w - 1), static_cast<std::int32_t>(c), ln});
}

// Builds the corpus from (doc, word, count) entries, rejecting repeated (doc, word) pairs.
Corpus build(const fs::path& file, std::vector<Entry>& entries, std::int64_t num_docs,
             std::int32_t num_words, std::vector<std::string> vocabulary) {
  auto less = [](const Entry& a, const Entry& b) {
    return a.doc != b.doc ? a.doc < b.doc : a.word < b.word;
  };
  if (!std::is_sorted(entries.begin(), entries.end(), less)) {
    std::stable_sort(entries.begin(), entries.end(), less);
  }
  for (std::size_t i = 1; i < entries.size(); ++i) {
    if (entries[i].doc == entries[i - 1].doc && entries[i].word == entries[i - 1].word) {
      const auto& e = entries[i - 1].line < entries[i].line ? entries[i] : entries[i - 1];
      const auto& first = entries[i - 1].line < entries[i].line ? entries[i - 1] : entries[i];
      throw Error::at_line(file, e.line,
                           "document " + std::to_string(e.doc + 1) + ", word " +
                               std::to_string(e.word + 1) + " repeats the entry of line " +
                               std::to_string(first.line));
    }
  }
  Corpus corpus(num_words, std::move(vocabulary));
  std::vector<std::int32_t> words;
  std::vector<std::int32_t> counts;
  std::size_t i = 0;
  for (std::int64_t d = 0; d < num_docs; ++d) {
    words.clear();
    counts.clear();
    while (i < entries.size() && entries[i].doc == d) {
      words.push_back(entries[i].word);
      counts.push_back(entries[i].count);
      ++i;
    }
    corpus.add_document(words, counts);
  }
  return corpus;
}

std::string read_text(const fs::path& path) { return core::read_file(path); }

// Holds declared sizes to the documented caps (corpus_io.hpp) before anything is allocated.
void check_caps(const fs::path& file, long line, std::int64_t num_docs, std::int64_t num_words) {
  if (num_words > kMaxCorpusWords) {
    throw Error::at_line(file, line,
                         "W = " + std::to_string(num_words) + " words is more than the " +
                             std::to_string(kMaxCorpusWords) + " a corpus may have");
  }
  if (num_docs > kMaxCorpusDocuments) {
    throw Error::at_line(file, line,
                         "D = " + std::to_string(num_docs) + " documents is more than the " +
                             std::to_string(kMaxCorpusDocuments) + " a corpus may have");
  }
}

// Which documents (0-based, in file order) a reader keeps, and their index in what it returns:
// all of them (the default), or every `shards`-th from `shard` (sharded reading under MPI).
struct DocumentFilter {
  int shard = 0;
  int shards = 1;
  [[nodiscard]] bool keeps(std::int64_t doc) const { return doc % shards == shard; }
  [[nodiscard]] std::int64_t index(std::int64_t doc) const { return (doc - shard) / shards; }
  /// How many of `documents` it keeps.
  [[nodiscard]] std::int64_t count(std::int64_t documents) const {
    return documents > shard ? (documents - shard + shards - 1) / shards : 0;
  }
};

// What a parser found: the kept entries (documents renumbered by the filter) and the whole file's
// sizes.
struct Parsed {
  std::vector<Entry> entries;
  std::int64_t documents = 0;  // D of the whole file
  std::int32_t words = 0;      // W
  std::int64_t tokens = 0;     // tokens of the whole file
  std::vector<std::string> vocabulary;
};

// UCI bag of words (docword.txt: D, W, NNZ, then 'docID wordID count' lines) from a line source
// (Lines over a buffer, or StreamLines over a file); `reserve` bounds the entries reserved up
// front (0: none), so that a header's NNZ is never trusted for an allocation.
template <class LineSource>
Parsed parse_uci(LineSource& lines, const fs::path& docword, const fs::path& vocab,
                 const DocumentFilter& keep, std::size_t reserve) {
  std::string_view line;
  std::int64_t header[3] = {0, 0, 0};
  const char* names[3] = {"D (documents)", "W (words)", "NNZ (entries)"};
  for (int h = 0; h < 3; ++h) {
    do {
      if (!lines.next(line)) {
        throw Error::in_file(docword, std::string("truncated: no header line ") + names[h]);
      }
    } while (is_blank(line));
    const auto f = fields(line);
    if (f.size() != 1) {
      throw Error::at_line(docword, lines.number(),
                           std::string("expected one integer, ") + names[h]);
    }
    header[h] = integer_field(docword, lines.number(), f[0], names[h]);
    if (header[h] < 0) {
      throw Error::at_line(docword, lines.number(), std::string(names[h]) + " is negative");
    }
  }
  const std::int64_t num_docs = header[0];
  const std::int64_t num_words = header[1];
  const std::int64_t nnz = header[2];
  check_caps(docword, lines.number(), num_docs, num_words);
  if (num_words > std::numeric_limits<std::int32_t>::max() ||
      num_docs > std::numeric_limits<std::int32_t>::max()) {
    throw Error::in_file(docword, "absurd header: D = " + std::to_string(num_docs) +
                                      ", W = " + std::to_string(num_words));
  }
  if (num_docs > 0 && num_words > 0 && nnz / num_docs > num_words) {
    throw Error::in_file(docword, "header NNZ = " + std::to_string(nnz) + " exceeds D x W");
  }
  Parsed p;
  p.documents = num_docs;
  p.words = static_cast<std::int32_t>(num_words);
  if (!vocab.empty()) {
    p.vocabulary = read_vocabulary(vocab);
    if (static_cast<std::int64_t>(p.vocabulary.size()) != num_words) {
      throw Error::in_file(vocab, "has " + std::to_string(p.vocabulary.size()) + " words but " +
                                      docword.string() + " says W = " + std::to_string(num_words));
    }
  }
  p.entries.reserve(std::min<std::size_t>(static_cast<std::size_t>(nnz), reserve));
  std::int64_t seen = 0;
  std::vector<Entry> one;
  while (lines.next(line)) {
    if (is_blank(line)) continue;
    const auto f = fields(line);
    const long ln = lines.number();
    if (f.size() != 3) {
      throw Error::at_line(docword, ln, "expected 'docID wordID count', found " + quote(line));
    }
    const std::int64_t d = integer_field(docword, ln, f[0], "docID");
    const std::int64_t w = integer_field(docword, ln, f[1], "wordID");
    const std::int64_t c = integer_field(docword, ln, f[2], "count");
    if (seen == nnz) {
      throw Error::at_line(docword, ln,
                           "more entries than the header's NNZ = " + std::to_string(nnz));
    }
    ++seen;
    one.clear();
    add_entry(one, docword, ln, d, w, c, num_docs, num_words, 1,
              {"docID", "wordID", "more entries than the header's NNZ = "});
    p.tokens += c;
    if (keep.keeps(one.front().doc)) {
      Entry e = one.front();
      e.doc = keep.index(e.doc);
      p.entries.push_back(e);
    }
  }
  if (seen < nnz) {
    throw Error::in_file(docword, "truncated: the header's NNZ is " + std::to_string(nnz) +
                                      " but the file has " + std::to_string(seen) + " entries");
  }
  return p;
}

// LDA-C (a line per document: 'N id:count ...', ids from 0) from a line source; W is the
// vocabulary's size, or the largest id + 1 without one.
template <class LineSource>
Parsed parse_ldac(LineSource& lines, const fs::path& file, std::vector<std::string> vocabulary,
                  const DocumentFilter& keep) {
  std::string_view line;
  Parsed p;
  std::int64_t doc = 0;
  std::int64_t max_id = -1;
  const std::int64_t limit =
      vocabulary.empty() ? kMaxCorpusWords : static_cast<std::int64_t>(vocabulary.size());
  while (lines.next(line)) {
    const long ln = lines.number();
    if (is_blank(line)) {
      throw Error::at_line(file, ln, "blank line (an empty document is written '0')");
    }
    const auto f = fields(line);
    const std::int64_t n = integer_field(file, ln, f[0], "the number of distinct words");
    if (n < 0 || n != static_cast<std::int64_t>(f.size()) - 1) {
      throw Error::at_line(file, ln,
                           "the line starts with N = " + std::to_string(n) + " but has " +
                               std::to_string(f.size() - 1) + " id:count pairs");
    }
    const bool mine = keep.keeps(doc);
    for (std::size_t i = 1; i < f.size(); ++i) {
      const auto colon = f[i].find(':');
      if (colon == std::string_view::npos) {
        throw Error::at_line(file, ln, "expected id:count, found " + quote(f[i]));
      }
      const std::int64_t id = integer_field(file, ln, f[i].substr(0, colon), "word id");
      const std::int64_t c = integer_field(file, ln, f[i].substr(colon + 1), "count");
      if (id < 0 || id >= limit) {
        std::string msg = "word id " + std::to_string(id) + " outside [0, ";
        msg += std::to_string(limit) + ")";
        msg += vocabulary.empty() ? " (the cap on W without a vocabulary)"
                                  : " (the vocabulary's size)";
        throw Error::at_line(file, ln, msg);
      }
      if (c <= 0 || c > std::numeric_limits<std::int32_t>::max()) {
        throw Error::at_line(file, ln, "count " + std::to_string(c) + " is not positive");
      }
      max_id = std::max(max_id, id);
      p.tokens += c;
      if (mine) {
        p.entries.push_back(
            {keep.index(doc), static_cast<std::int32_t>(id), static_cast<std::int32_t>(c), ln});
      }
    }
    ++doc;
    if (doc > kMaxCorpusDocuments) check_caps(file, ln, doc, 0);
  }
  if (doc == 0) throw Error::in_file(file, "no documents");
  p.documents = doc;
  p.words = vocabulary.empty() ? static_cast<std::int32_t>(max_id + 1)
                               : static_cast<std::int32_t>(vocabulary.size());
  p.vocabulary = std::move(vocabulary);
  return p;
}

}  // namespace

CorpusFormat parse_corpus_format(std::string_view name) {
  if (name == "uci") return CorpusFormat::kUci;
  if (name == "ldac") return CorpusFormat::kLdac;
  if (name == "mm") return CorpusFormat::kMatrixMarket;
  std::string msg = "unknown corpus format ";
  msg += quote(name);
  msg += " (expected uci, ldac or mm)";
  throw Error(msg);
}

std::string_view to_string(CorpusFormat format) {
  switch (format) {
    case CorpusFormat::kUci:
      return "uci";
    case CorpusFormat::kLdac:
      return "ldac";
    case CorpusFormat::kMatrixMarket:
      return "mm";
  }
  return "?";
}

std::vector<std::string> read_vocabulary(const fs::path& path) {
  const std::string text = read_text(path);
  Lines lines(text);
  std::string_view line;
  std::vector<std::string> words;
  std::unordered_set<std::string_view> seen;
  while (lines.next(line)) {
    // Surrounding spaces are not part of a word.
    while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
    while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
    if (line.empty()) throw Error::at_line(path, lines.number(), "blank line in a vocabulary");
    if (!seen.insert(line).second) {
      throw Error::at_line(path, lines.number(), "word " + quote(line) + " appears twice");
    }
    words.emplace_back(line);
  }
  if (words.empty()) throw Error::in_file(path, "empty vocabulary");
  if (static_cast<std::int64_t>(words.size()) > kMaxCorpusWords) {
    throw Error::in_file(path, std::to_string(words.size()) + " words, more than the " +
                                   std::to_string(kMaxCorpusWords) + " a vocabulary may have");
  }
  return words;
}

Corpus read_uci(const fs::path& docword, const fs::path& vocab) {
  const std::string text = read_text(docword);
  Lines lines(text);
  Parsed p = parse_uci(lines, docword, vocab, {}, text.size() / 6 + 1);
  return build(docword, p.entries, p.documents, p.words, std::move(p.vocabulary));
}

Corpus read_ldac(const fs::path& file, const fs::path& vocab) {
  std::vector<std::string> vocabulary;
  if (!vocab.empty()) vocabulary = read_vocabulary(vocab);
  const std::string text = read_text(file);
  Lines lines(text);
  Parsed p = parse_ldac(lines, file, std::move(vocabulary), {});
  return build(file, p.entries, p.documents, p.words, std::move(p.vocabulary));
}

Corpus read_matrix_market(const fs::path& file, const fs::path& vocab) {
  const std::string text = read_text(file);
  Lines lines(text);
  std::string_view line;
  if (!lines.next(line)) throw Error::in_file(file, "empty file");
  auto banner = fields(line);
  std::vector<std::string> lower;
  for (auto b : banner) {
    std::string s(b);
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    lower.push_back(s);
  }
  if (lower.size() != 5 || lower[0] != "%%matrixmarket" || lower[1] != "matrix" ||
      lower[2] != "coordinate") {
    throw Error::at_line(file, 1, "expected '%%MatrixMarket matrix coordinate <field> general'");
  }
  const std::string& field = lower[3];
  if (field != "integer" && field != "real" && field != "pattern") {
    throw Error::at_line(file, 1, "field '" + field + "' is not integer, real or pattern");
  }
  if (lower[4] != "general") {
    throw Error::at_line(file, 1, "symmetry '" + lower[4] + "' is not 'general'");
  }
  std::int64_t size[3] = {0, 0, 0};
  for (;;) {
    if (!lines.next(line)) throw Error::in_file(file, "truncated: no size line");
    if (is_blank(line) || line.front() == '%') continue;
    const auto f = fields(line);
    if (f.size() != 3) {
      throw Error::at_line(file, lines.number(),
                           "expected the size line 'documents words entries'");
    }
    for (int i = 0; i < 3; ++i) {
      size[i] = integer_field(file, lines.number(), f[static_cast<std::size_t>(i)], "a size");
      if (size[i] < 0) throw Error::at_line(file, lines.number(), "negative size");
    }
    break;
  }
  const std::int64_t num_docs = size[0];
  const std::int64_t num_words = size[1];
  const std::int64_t nnz = size[2];
  check_caps(file, lines.number(), num_docs, num_words);
  if (num_words > std::numeric_limits<std::int32_t>::max() ||
      num_docs > std::numeric_limits<std::int32_t>::max() ||
      (num_docs > 0 && num_words > 0 && nnz / num_docs > num_words)) {
    throw Error::in_file(file, "absurd size line");
  }
  std::vector<std::string> vocabulary;
  if (!vocab.empty()) {
    vocabulary = read_vocabulary(vocab);
    if (static_cast<std::int64_t>(vocabulary.size()) != num_words) {
      throw Error::in_file(vocab, "has " + std::to_string(vocabulary.size()) + " words but " +
                                      file.string() + " has " + std::to_string(num_words) +
                                      " columns");
    }
  }
  std::vector<Entry> entries;
  entries.reserve(static_cast<std::size_t>(std::min<std::int64_t>(nnz, text.size() / 6 + 1)));
  const std::size_t want = field == "pattern" ? 2 : 3;
  while (lines.next(line)) {
    if (is_blank(line) || line.front() == '%') continue;
    const long ln = lines.number();
    const auto f = fields(line);
    if (f.size() != want) {
      throw Error::at_line(file, ln,
                           std::string("expected 'document word") + (want == 3 ? " count'" : "'") +
                               ", found " + quote(line));
    }
    const std::int64_t d = integer_field(file, ln, f[0], "the row (document)");
    const std::int64_t w = integer_field(file, ln, f[1], "the column (word)");
    std::int64_t c = 1;
    if (field == "integer") {
      c = integer_field(file, ln, f[2], "count");
    } else if (field == "real") {
      double v = 0;
      const auto r = std::from_chars(f[2].data(), f[2].data() + f[2].size(), v);
      if (r.ec != std::errc() || r.ptr != f[2].data() + f[2].size() || !std::isfinite(v) ||
          v != std::floor(v) || std::abs(v) > 2e9) {
        throw Error::at_line(file, ln, "count " + quote(f[2]) + " is not a whole number");
      }
      c = static_cast<std::int64_t>(v);
    }
    add_entry(entries, file, ln, d, w, c, num_docs, num_words, nnz,
              {"document", "word", "more entries than the size line's "});
  }
  if (static_cast<std::int64_t>(entries.size()) < nnz) {
    throw Error::in_file(file, "truncated: the size line promises " + std::to_string(nnz) +
                                   " entries but the file has " + std::to_string(entries.size()));
  }
  return build(file, entries, num_docs, static_cast<std::int32_t>(num_words),
               std::move(vocabulary));
}

namespace {

// The one file in `dir` named `exact`, else the one whose name matches prefix*suffix.
fs::path find_one(const fs::path& dir, const std::string& exact, const std::string& prefix,
                  const std::vector<std::string>& suffixes, bool required) {
  if (fs::is_regular_file(dir / exact)) return dir / exact;
  std::vector<fs::path> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file()) continue;
    const std::string name = e.path().filename().string();
    for (const auto& suffix : suffixes) {
      if (name.size() >= prefix.size() + suffix.size() && name.rfind(prefix, 0) == 0 &&
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
        found.push_back(e.path());
        break;
      }
    }
  }
  std::sort(found.begin(), found.end());
  if (found.size() == 1) return found[0];
  if (found.size() > 1) {
    throw Error::in_file(dir, "several candidates for " + exact + ": " +
                                  found[0].filename().string() + ", " +
                                  found[1].filename().string());
  }
  if (required) throw Error::in_file(dir, "no " + exact + " in this directory");
  return {};
}

}  // namespace

CorpusFiles find_corpus_files(const fs::path& dir_or_file, CorpusFormat format) {
  if (!fs::exists(dir_or_file)) throw Error::in_file(dir_or_file, "no such file or directory");
  const bool is_dir = fs::is_directory(dir_or_file);
  const fs::path dir = is_dir ? dir_or_file : dir_or_file.parent_path();
  const fs::path vocab_dir = dir.empty() ? fs::path(".") : dir;
  switch (format) {
    case CorpusFormat::kUci: {
      const fs::path docword =
          is_dir ? find_one(dir, "docword.txt", "docword.", {".txt"}, true) : dir_or_file;
      fs::path vocab = vocab_dir / "vocab.txt";
      if (!fs::is_regular_file(vocab)) {
        // docword.NAME.txt goes with vocab.NAME.txt.
        std::string name = docword.filename().string();
        if (name.rfind("docword.", 0) == 0) name = "vocab." + name.substr(8);
        vocab = vocab_dir / name;
        if (!fs::is_regular_file(vocab)) {
          throw Error::in_file(vocab_dir, "no vocab.txt beside " + docword.filename().string());
        }
      }
      return {docword, vocab};
    }
    case CorpusFormat::kLdac: {
      const fs::path file =
          is_dir ? find_one(dir, "corpus.ldac", "", {".ldac", ".dat"}, true) : dir_or_file;
      const fs::path vocab =
          fs::is_regular_file(vocab_dir / "vocab.txt") ? vocab_dir / "vocab.txt" : fs::path();
      return {file, vocab};
    }
    case CorpusFormat::kMatrixMarket: {
      const fs::path file =
          is_dir ? find_one(dir, "corpus.mm", "", {".mm", ".mtx"}, true) : dir_or_file;
      const fs::path vocab =
          fs::is_regular_file(vocab_dir / "vocab.txt") ? vocab_dir / "vocab.txt" : fs::path();
      return {file, vocab};
    }
  }
  return {};
}

namespace {

// The documents of `keep`'s shard among UCI or LDA-C lines, read as a stream (no rank holds the
// whole file).
CorpusShard read_shard(const fs::path& file, const fs::path& vocab, CorpusFormat format,
                       const DocumentFilter& keep) {
  std::vector<std::string> vocabulary;
  if (format == CorpusFormat::kLdac && !vocab.empty()) vocabulary = read_vocabulary(vocab);
  StreamLines lines(file);
  Parsed p = format == CorpusFormat::kUci ? parse_uci(lines, file, vocab, keep, 0)
                                          : parse_ldac(lines, file, std::move(vocabulary), keep);
  CorpusShard out;
  out.shard = keep.shard;
  out.shards = keep.shards;
  out.total_documents = p.documents;
  out.total_tokens = p.tokens;
  out.documents = build(file, p.entries, keep.count(p.documents), p.words, std::move(p.vocabulary));
  out.checksum = lines.checksum();
  return out;
}

}  // namespace

CorpusShard read_corpus_shard(const fs::path& dir_or_file, CorpusFormat format, int shard,
                              int shards) {
  if (shards < 1 || shard < 0 || shard >= shards) {
    throw InternalError("read_corpus_shard: shard " + std::to_string(shard) + " of " +
                        std::to_string(shards));
  }
  const CorpusFiles files = find_corpus_files(dir_or_file, format);
  CorpusShard out;
  switch (format) {
    case CorpusFormat::kUci:
    case CorpusFormat::kLdac:
      out = read_shard(files.file, files.vocabulary, format, {shard, shards});
      break;
    case CorpusFormat::kMatrixMarket:
      throw Error::in_file(files.file,
                           "a MatrixMarket corpus cannot be read in shards (use uci or ldac)");
  }
  std::error_code ec;
  const auto size = fs::file_size(files.file, ec);
  out.bytes = ec ? 0 : static_cast<std::uint64_t>(size);
  return out;
}

Corpus read_corpus(const fs::path& dir_or_file, CorpusFormat format) {
  const CorpusFiles files = find_corpus_files(dir_or_file, format);
  switch (format) {
    case CorpusFormat::kUci:
      return read_uci(files.file, files.vocabulary);
    case CorpusFormat::kLdac:
      return read_ldac(files.file, files.vocabulary);
    case CorpusFormat::kMatrixMarket:
      return read_matrix_market(files.file, files.vocabulary);
  }
  return {};
}

std::string format_corpus(const Corpus& corpus, CorpusFormat format) {
  std::string out;
  out.reserve(corpus.num_entries() * 12 + 64);
  char buf[64];
  auto put = [&](std::int64_t v) {
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
  };
  const auto docs = static_cast<std::int64_t>(corpus.num_documents());
  switch (format) {
    case CorpusFormat::kUci:
    case CorpusFormat::kMatrixMarket:
      if (format == CorpusFormat::kMatrixMarket) {
        out += "%%MatrixMarket matrix coordinate integer general\n";
        put(docs);
        out += ' ';
        put(corpus.num_words());
        out += ' ';
        put(static_cast<std::int64_t>(corpus.num_entries()));
        out += '\n';
      } else {
        put(docs);
        out += '\n';
        put(corpus.num_words());
        out += '\n';
        put(static_cast<std::int64_t>(corpus.num_entries()));
        out += '\n';
      }
      for (std::int64_t d = 0; d < docs; ++d) {
        const auto doc = corpus.document(static_cast<std::size_t>(d));
        for (std::size_t i = 0; i < doc.size(); ++i) {
          put(d + 1);
          out += ' ';
          put(doc.words[i] + 1);
          out += ' ';
          put(doc.counts[i]);
          out += '\n';
        }
      }
      break;
    case CorpusFormat::kLdac:
      for (std::int64_t d = 0; d < docs; ++d) {
        const auto doc = corpus.document(static_cast<std::size_t>(d));
        put(static_cast<std::int64_t>(doc.size()));
        for (std::size_t i = 0; i < doc.size(); ++i) {
          out += ' ';
          put(doc.words[i]);
          out += ':';
          put(doc.counts[i]);
        }
        out += '\n';
      }
      break;
  }
  return out;
}

void write_corpus(const Corpus& corpus, const fs::path& dir, CorpusFormat format) {
  const char* name = format == CorpusFormat::kUci    ? "docword.txt"
                     : format == CorpusFormat::kLdac ? "corpus.ldac"
                                                     : "corpus.mm";
  core::write_file_atomic(dir / name, format_corpus(corpus, format));
  if (!corpus.vocabulary().empty()) {
    std::string v;
    for (const auto& w : corpus.vocabulary()) {
      v += w;
      v += '\n';
    }
    core::write_file_atomic(dir / "vocab.txt", v);
  }
}

}  // namespace proprio::topics
