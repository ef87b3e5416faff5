// CLI11 options whose values are the names of a Choices<E> (meso/scene/choices.h): checked
// against its table and converted as they are parsed (CLI11 runs the check before the function).
#pragma once

#include "meso/scene/choices.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace meso::app {

template <class E>
CLI::Option* addChoice(CLI::App* app, const std::string& name, std::optional<E>& value,
                       const std::string& help) {
  return app
      ->add_option_function<std::string>(
          name, [&value](const std::string& s) { value = meso::parseChoice<E>(s); }, help)
      ->check(CLI::IsMember(meso::choiceNames<E>()));
}
template <class E>
CLI::Option* addChoice(CLI::App* app, const std::string& name, E& value, const std::string& help) {
  return app
      ->add_option_function<std::string>(
          name, [&value](const std::string& s) { value = *meso::parseChoice<E>(s); }, help)
      ->check(CLI::IsMember(meso::choiceNames<E>()))
      ->default_str(meso::choiceName(value));
}
template <class E>
CLI::Option* addChoices(CLI::App* app, const std::string& name, std::vector<E>& values,
                        const std::string& help) {
  std::string defaults;
  for (E v : values) defaults += (defaults.empty() ? "" : ",") + std::string(meso::choiceName(v));
  return app
      ->add_option_function<std::vector<std::string>>(
          name,
          [&values](const std::vector<std::string>& names) {
            values.clear();
            for (const std::string& s : names) values.push_back(*meso::parseChoice<E>(s));
          },
          help)
      ->delimiter(',')
      ->check(CLI::IsMember(meso::choiceNames<E>()))
      ->default_str(defaults);
}

}  // namespace meso::app
