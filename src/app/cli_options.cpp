// The checks addOption adds by kind of value (cli_options.h).
#include "cli_options.h"

#include "cli_values.h"

namespace meso::app {

CLI::Validator finiteCheck() {
  return CLI::Validator([](std::string& text) { return finiteNumberProblem(text); }, "FINITE",
                        "finite number");
}

CLI::Validator wholeNumberCheck() {
  return CLI::Validator([](std::string& text) { return unsignedNumberProblem(text); }, "UNSIGNED",
                        "whole number of 0 or more");
}

CLI::Validator nonEmptyCheck() {
  return CLI::Validator(
      [](std::string& text) {
        return text.empty() ? std::string("expected a value, got an empty string") : std::string();
      },
      "", "non-empty");
}

}  // namespace meso::app
