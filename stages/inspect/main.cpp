// syn-inspect FILE: prints what a file holds, as JSON on stdout.
//   *.h5   — any intermediate's root attributes and every dataset's shape;
//   *.urdf — the robot model as synsculpt loads it (nq, nu, mass, links, joints).
#include <iostream>

#include "common/cli.h"
#include "common/intermediate_file.h"
#include "stages/inspect/describe_model.h"

int main(int argc, char** argv) {
  CLI::App app{"Print an intermediate file's attributes and dataset shapes, or a URDF model's structure, as JSON.",
               "syn-inspect"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common, /*with_output=*/false);
  std::string path;
  std::string floating_base = "auto";
  app.add_option("FILE", path, "An intermediate file (.h5) or a robot model (.urdf)")->required();
  app.add_option("--floating-base", floating_base, "For a URDF: auto | free | fixed (see syn-retarget --help)")
      ->check(CLI::IsMember({"auto", "free", "fixed"}));
  return syn::RunTool(app, argc, argv, [&] {
    const bool is_urdf = path.size() >= 5 && path.compare(path.size() - 5, 5, ".urdf") == 0;
    nlohmann::json description = is_urdf ? syn::DescribeModel(path, floating_base) : syn::DescribeIntermediateFile(path);
    syn::MakeJsonUtf8(description);  // names from files may be Latin-1 or garbage (common/text_encoding.h)
    if (is_urdf) syn::PrintNotes("syn-inspect", description["notes"].get<std::vector<std::string>>(), common.verbose);
    std::cout << description.dump(2) << "\n";
  });
}
