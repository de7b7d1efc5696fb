// proprio._proprio.planning and .loop: the push planner's options and `proprio push` as a call
// (look, find putative objects, plan one push, execute it on a new simulated table, score it).
#include "common.hpp"
#include "options.hpp"
#include "proprio/loop/push_run.hpp"
#include "proprio/planning/push_planner.hpp"

namespace proprio::python {

void bind_planning(py::module_& m) {
  bind_options<planning::PushPlanOptions>(
      m, "PushPlanOptions",
      "Push planning (thesis 7.2.1): putative objects as feature-density blobs, sampled paths.");
}

void bind_loop(py::module_& m) {
  bind_options<loop::PushOptions>(
      m, "PushOptions",
      "One look-plan-push on a new simulated table (`proprio push`); the table and the planner "
      "are passed beside it to run_push.");
  m.def(
      "run_push",
      [](const loop::PushOptions& options, const sim::TableOptions& table,
         const planning::PushPlanOptions& plan) {
        auto o = options;
        o.table = table;
        o.plan = plan;
        o.validate();
        const auto provenance = python_provenance(table.seed);
        auto r = [&] {
          py::gil_scoped_release release;
          return loop::run_push(o, provenance);
        }();
        py::dict d;
        d["message"] = r.message;
        d["brief"] = r.brief();
        d["document"] = json_to_python(r.document);
        return d;
      },
      py::arg("options") = loop::PushOptions{}, py::arg("table") = sim::TableOptions{},
      py::arg("plan") = planning::PushPlanOptions{},
      "`proprio push` as a call: builds the table, looks, plans one push of the chosen object, "
      "executes it and scores it against the ground truth. Returns a dict: message, brief, and "
      "document (the push.json record as Python objects). GIL released.");
}

}  // namespace proprio::python
