#include "proprio/core/checkpoint.hpp"

#include <charconv>
#include <system_error>

#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"

namespace proprio::core {

void CheckpointOptions::validate() const {
  if (every < 1) throw Error("--checkpoint-every must be at least 1");
}

std::uint64_t fnv1a(std::string_view bytes, std::uint64_t hash) {
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 1099511628211ULL;
  }
  return hash;
}

std::string exact_text(double value) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  ensure(r.ec == std::errc(), "exact_text: to_chars failed");
  return {buf, r.ptr};
}

namespace {

void put_text32(std::string& out, std::string_view s) {
  put_binary<std::uint32_t>(out, static_cast<std::uint32_t>(s.size()));
  out.append(s);
}

std::string get_text32(BinaryReader& in, const char* what) {
  const auto n = in.get<std::uint32_t>(what);
  return std::string(in.take(n, what));  // take() checks n against the bytes left first
}

}  // namespace

std::string serialize_checkpoint(const Checkpoint& c) {
  ensure(c.options.size() <= kMaxCheckpointOptions, "checkpoint: too many options");
  std::string p;
  put_text32(p, c.kind);
  put_binary<std::uint64_t>(p, c.input_checksum);
  put_binary<std::uint32_t>(p, static_cast<std::uint32_t>(c.options.size()));
  for (const auto& [name, value] : c.options) {
    put_text32(p, name);
    put_text32(p, value);
  }
  put_binary<std::uint64_t>(p, c.state.size());
  p.append(c.state);
  return frame_binary(kCheckpointFormat, p);
}

namespace {

Checkpoint parse_payload(std::string_view payload, const std::filesystem::path& source) {
  BinaryReader in(payload, source, kCheckpointFormat.kind);
  Checkpoint c;
  c.kind = get_text32(in, "the kind");
  c.input_checksum = in.get<std::uint64_t>("the input checksum");
  const auto n = in.get<std::uint32_t>("the number of options");
  // Each option takes at least 8 bytes: a count beyond what is left is refused before reserving.
  if (n > kMaxCheckpointOptions || n > in.left() / 8) {
    throw Error::in_file(source, "corrupt checkpoint file: " + std::to_string(n) + " options");
  }
  c.options.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    std::string name = get_text32(in, "an option's name");
    std::string value = get_text32(in, "an option's value");
    c.options.emplace_back(std::move(name), std::move(value));
  }
  const auto s = in.get<std::uint64_t>("the state's size");
  c.state = std::string(in.take(s, "the state"));
  if (in.left() != 0) {
    throw Error::in_file(
        source, "corrupt checkpoint file: " + std::to_string(in.left()) + " bytes after the state");
  }
  return c;
}

}  // namespace

Checkpoint parse_checkpoint(std::string_view bytes, const std::filesystem::path& source) {
  return parse_payload(unframe_binary(bytes, kCheckpointFormat, source), source);
}

void save_checkpoint(const Checkpoint& checkpoint, const std::filesystem::path& path) {
  write_file_atomic(path, serialize_checkpoint(checkpoint));
}

Checkpoint load_checkpoint(const std::filesystem::path& path) {
  return parse_payload(read_binary_file(path, kCheckpointFormat), path);
}

void check_checkpoint_matches(const Checkpoint& found, const Checkpoint& expected,
                              const std::filesystem::path& source, std::string_view input_name) {
  if (found.kind != expected.kind) {
    throw Error::in_file(source, "is a checkpoint of " + found.kind + ", not of " + expected.kind);
  }
  if (found.input_checksum != expected.input_checksum) {
    std::string msg = "is a checkpoint of another ";
    msg += input_name;
    msg += " (its checksum differs): resume with the same input";
    throw Error::in_file(source, msg);
  }
  for (const auto& [name, value] : expected.options) {
    std::string had = "(none)";
    for (const auto& [n, v] : found.options) {
      if (n == name) had = v;
    }
    if (had != value) {
      std::string msg = "was written with ";
      msg += name;
      msg += " = ";
      msg += had;
      msg += ", this run has ";
      msg += value;
      msg += ": resume with the same options";
      throw Error::in_file(source, msg);
    }
  }
  if (found.options.size() != expected.options.size()) {
    throw Error::in_file(source, "was written with other options: resume with the same options");
  }
}

}  // namespace proprio::core
