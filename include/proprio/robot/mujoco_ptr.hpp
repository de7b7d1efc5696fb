#pragma once
// Owning handles for MuJoCo's model and data, and model loading with file-naming errors.
// Any module that runs MuJoCo (robot, sim) uses these instead of raw mj_delete* calls.

#include <mujoco/mujoco.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace proprio::robot {

struct ModelDeleter {
  void operator()(mjModel* model) const noexcept { mj_deleteModel(model); }
};
struct DataDeleter {
  void operator()(mjData* data) const noexcept { mj_deleteData(data); }
};

/// Owning mjModel (constant once compiled).
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
/// Owning mjData (the simulation state and workspace for one model).
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

/// Compiles an MJCF (or MJB) file. Throws Error naming the file with MuJoCo's error text when the
/// file is missing or does not compile, and when compiling it raises a warning (a model that
/// warns is a broken model here).
ModelPtr load_model(const std::filesystem::path& path);

/// Compiles an MJCF document given as text; `name` stands for the file in error messages.
/// Relative <include> paths resolve against the current directory.
ModelPtr load_model_from_string(const std::string& xml, const std::string& name = "<string>");

/// A deep copy of a model (for variants, e.g. with gravity switched off).
ModelPtr copy_model(const mjModel& model);

/// Fresh data for `model`, at the model's reference configuration qpos0.
DataPtr make_data(const mjModel& model);

/// The run-time warnings MuJoCo has counted in `data` (mjData::warning), one line each, e.g.
/// "mjWARN_BADQACC x3 (last info 2)"; empty when there were none.
std::vector<std::string> warnings(const mjData& data);

}  // namespace proprio::robot
