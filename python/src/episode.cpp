#include "common.hpp"
namespace proprio::python {
void bind_episode(py::module_& /*m*/) {}
}  // namespace proprio::python
