// How meso's commands register options on CLI11. addOption adds the checks a value's C++ type
// needs after the caller's own: CLI11 reads "nan" and "inf" into floats and Range() lets NaN
// through, so every floating-point value must be a finite number; it wraps "-1" into an unsigned
// option, so every unsigned one must be a whole number of 0 or more; and a text or path value may
// not be empty (`-o ''` is refused, not taken for the default). Choice options take the names of a
// Choices<E> (meso/scene/choices.h), checked against its table and converted as they are parsed.
#pragma once

#include "meso/scene/choices.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace meso::app {

// The checks addOption adds, by kind of value.
CLI::Validator finiteCheck();
CLI::Validator wholeNumberCheck();
CLI::Validator nonEmptyCheck();

namespace detail {
template <class T>
struct ValueOf {
  using type = T;
};
template <class T>
struct ValueOf<std::optional<T>> : ValueOf<T> {};
template <class T>
struct ValueOf<std::vector<T>> : ValueOf<T> {};
}  // namespace detail

// Adds option `name` writing into `value`, with `checks` (CLI::Range, CLI::ExistingFile, ...) and
// then the check its type needs (each element of a vector, the value of an optional).
template <class T, class... Checks>
CLI::Option* addOption(CLI::App* app, const std::string& name, T& value, const std::string& help,
                       const Checks&... checks) {
  CLI::Option* option = app->add_option(name, value, help);
  (option->check(checks), ...);
  using V = typename detail::ValueOf<T>::type;
  if constexpr (std::is_floating_point_v<V>)
    option->check(finiteCheck());
  else if constexpr (std::is_unsigned_v<V> && !std::is_same_v<V, bool>)
    option->check(wholeNumberCheck());
  else if constexpr (std::is_same_v<V, std::string> || std::is_same_v<V, std::filesystem::path>)
    option->check(nonEmptyCheck());
  return option;
}

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
