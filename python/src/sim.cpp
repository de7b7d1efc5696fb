#include "common.hpp"
namespace proprio::python {
void bind_sim(py::module_& /*m*/) {}
}  // namespace proprio::python
