#include "common.hpp"
namespace proprio::python {
void bind_features(py::module_& /*m*/) {}
}  // namespace proprio::python
