#include "proprio/robot/mujoco_ptr.hpp"

#include <array>
#include <cstring>
#include <system_error>

#include "proprio/core/error.hpp"

namespace proprio::robot {
namespace {

constexpr int kErrorSize = 1000;

ModelPtr checked(mjModel* model, const char* error, const std::string& name) {
  if (model == nullptr) {
    std::string message = "MuJoCo could not load the model: ";
    message += error[0] != '\0' ? error : "unknown error";
    throw Error::in_file(name, message);
  }
  ModelPtr owned(model);
  if (error[0] != '\0') {
    std::string message = "MuJoCo warns while compiling the model: ";
    message += error;
    throw Error::in_file(name, message);
  }
  return owned;
}

}  // namespace

ModelPtr load_model(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw Error::in_file(path, "no such model file");
  }
  std::array<char, kErrorSize> error{};
  mjModel* model = mj_loadXML(path.c_str(), nullptr, error.data(), kErrorSize);
  return checked(model, error.data(), path.string());
}

ModelPtr load_model_from_string(const std::string& xml, const std::string& name) {
  // mjVFS holds fixed arrays of file slots (megabytes): keep it off the stack.
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const std::string file = "proprio_model_from_string.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), file.c_str(), static_cast<int>(xml.size())) != 0) {
    mj_deleteVFS(vfs.get());
    throw Error::in_file(name, "MuJoCo could not hold the model text in its virtual file system");
  }
  const int slot = mj_findFileVFS(vfs.get(), file.c_str());
  std::memcpy(vfs->filedata[slot], xml.data(), xml.size());
  std::array<char, kErrorSize> error{};
  mjModel* model = mj_loadXML(file.c_str(), vfs.get(), error.data(), kErrorSize);
  mj_deleteVFS(vfs.get());
  return checked(model, error.data(), name);
}

ModelPtr copy_model(const mjModel& model) {
  ModelPtr copy(mj_copyModel(nullptr, &model));
  if (!copy) throw Error("MuJoCo could not copy the model (out of memory)");
  return copy;
}

DataPtr make_data(const mjModel& model) {
  DataPtr data(mj_makeData(&model));
  if (!data) throw Error("MuJoCo could not allocate mjData (out of memory)");
  return data;
}

std::vector<std::string> warnings(const mjData& data) {
  static constexpr std::array<const char*, mjNWARNING> kNames = {
      "mjWARN_INERTIA", "mjWARN_CONTACTFULL", "mjWARN_CNSTRFULL", "mjWARN_VGEOMFULL",
      "mjWARN_BADQPOS", "mjWARN_BADQVEL",     "mjWARN_BADQACC",   "mjWARN_BADCTRL"};
  std::vector<std::string> out;
  for (int i = 0; i < mjNWARNING; ++i) {
    const mjWarningStat& w = data.warning[i];
    if (w.number == 0) continue;
    std::string line = kNames[static_cast<std::size_t>(i)];
    line += " x";
    line += std::to_string(w.number);
    line += " (last info ";
    line += std::to_string(w.lastinfo);
    line += ")";
    out.push_back(std::move(line));
  }
  return out;
}

}  // namespace proprio::robot
