// proprio report: the page of a learn run (loop::write_learn_report; docs/report.md). Binds the
// options, makes the one library call, prints its brief, writes --json.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/core/files.hpp"
#include "proprio/loop/learn_report.hpp"

namespace proprio::app {

namespace {

struct ReportArgs {
  loop::LearnReportOptions options;
  std::string json;
};

}  // namespace

void register_report_commands(CLI::App& root, const Invocation& inv) {
  auto a = std::make_shared<ReportArgs>();
  auto* cmd = root.add_subcommand(
      "report",
      "The page of a learn run (proprio learn --out DIR): one offline HTML file with the table, "
      "every push and its segmentation, the words, topics and object models, the held-out "
      "confusion matrices and where the time went");
  cmd->add_option("dir", a->options.dir, "The run directory of proprio learn")->required();
  bind_options(cmd, a->options, {{}, {"dir"}});
  cmd->add_option("--json", a->json, "Also write what was written as JSON");
  cmd->callback([a, &inv] {
    if (!a->json.empty()) {
      std::vector<std::filesystem::path> inputs = loop::learn_report_inputs(a->options.dir);
      inputs.push_back(loop::learn_report_page(a->options));
      inputs.push_back(loop::learn_report_images(a->options));
      core::require_output_not_input(a->json, inputs, "--json");
    }
    const loop::LearnReportResult r = loop::write_learn_report(a->options, inv.provenance());
    std::printf("%s\n", r.brief().c_str());
    write_json_result(a->json, r.document);
  });
}

}  // namespace proprio::app
