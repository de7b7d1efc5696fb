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
  JsonFlag json;
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
  a->json.add_to(cmd, "what was written");
  cmd->callback([a, &inv] {
    if (a->json.given()) {
      std::vector<std::filesystem::path> inputs = loop::learn_report_inputs(a->options.dir);
      inputs.push_back(loop::learn_report_page(a->options));
      inputs.push_back(loop::learn_report_images(a->options));
      a->json.refuse(inputs);
    }
    const loop::LearnReportResult r = loop::write_learn_report(a->options, inv.provenance());
    std::printf("%s\n", r.brief().c_str());
    a->json.write(r.document);
  });
}

}  // namespace proprio::app
