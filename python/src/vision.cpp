#include "common.hpp"
namespace proprio::python {
void bind_vision(py::module_& /*m*/) {}
}  // namespace proprio::python
