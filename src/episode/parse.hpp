#pragma once
// Internal: the parsers behind episode.json, objects.json and arm.csv, reporting into a
// ProblemSink so that check_episode can list every problem and read_episode can stop at the first.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "problem_sink.hpp"
#include "proprio/core/json_io.hpp"
#include "proprio/episode/arm_sample.hpp"
#include "proprio/episode/episode_info.hpp"
#include "proprio/episode/objects.hpp"

namespace proprio::episode::detail {

/// The info, or none when a problem makes it unusable (every problem is reported).
std::optional<EpisodeInfo> parse_episode_info(const core::Json& j,
                                              const std::filesystem::path& file, ProblemSink& sink);

std::optional<std::vector<ObjectInfo>> parse_objects(const core::Json& j,
                                                     const std::filesystem::path& file,
                                                     ProblemSink& sink);

/// arm.csv's rows; none when any row is invalid. `joint_count`: the number of q columns that
/// episode.json declares (none: taken from the header). Reports every bad row, every frame
/// number out of sequence and every non-increasing time. `rows` is set to the number of data
/// rows, valid or not (0 when the header is wrong).
std::optional<std::vector<ArmSample>> parse_arm_csv(const std::string& text,
                                                    const std::filesystem::path& file,
                                                    std::optional<int> joint_count,
                                                    ProblemSink& sink, int& rows);

/// One line of arm.csv (with its newline); numbers in their shortest exact form.
std::string format_arm_row(int frame, const ArmSample& s);

}  // namespace proprio::episode::detail
