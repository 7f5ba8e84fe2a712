// A struct's fields as exact JSON and back, from one list of its fields: the per-run sums a
// reproduction's unit returns travel through JSON (evaluation/repro/repro_units.h), and every
// double survives the round trip bit for bit (JsonNumber; NaN as null). A struct opts in with a
// function found by argument-dependent lookup:
//   constexpr auto ExactFields(std::type_identity<Sums>) {
//     return std::make_tuple(ExactField("sum", &Sums::sum), ExactField("count", &Sums::count));
//   }
// Fields may be doubles, integers, booleans, strings, standard containers of them, structs that
// list their own fields, and maps from strings to any of these.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "evaluation/json_number.h"

namespace mavloc {

template <class T, class M>
struct ExactFieldOf {
  const char* name;
  M T::*member;
};

template <class T, class M>
constexpr ExactFieldOf<T, M> ExactField(const char* name, M T::*member) {
  return {name, member};
}

template <class T>
concept HasExactFields = requires {
  ExactFields(std::type_identity<T>{});
};

template <HasExactFields T>
nlohmann::json ToExactJson(const T& value);
template <HasExactFields T>
T FromExactJson(const nlohmann::json& json);

namespace exact_json_detail {

template <class>
struct IsStringMap : std::false_type {};
template <class V>
struct IsStringMap<std::map<std::string, V>> : std::true_type {};

template <class V>
nlohmann::json Write(const V& value);
template <class V>
V Read(const nlohmann::json& json);

template <class V>
nlohmann::json Write(const V& value) {
  if constexpr (std::is_floating_point_v<V>) {
    return JsonNumber(value);
  } else if constexpr (std::is_same_v<V, std::vector<double>>) {
    return JsonNumbers(value);
  } else if constexpr (IsStringMap<V>::value) {
    nlohmann::json object = nlohmann::json::object();
    for (const auto& [key, item] : value) object[key] = Write(item);
    return object;
  } else if constexpr (HasExactFields<V>) {
    return ToExactJson(value);
  } else {
    return nlohmann::json(value);
  }
}

template <class V>
V Read(const nlohmann::json& json) {
  if constexpr (std::is_floating_point_v<V>) {
    return NumberFromJson(json);
  } else if constexpr (std::is_same_v<V, std::vector<double>>) {
    return NumbersFromJson(json);
  } else if constexpr (IsStringMap<V>::value) {
    V out;
    for (const auto& [key, item] : json.items())
      out.emplace(key, Read<typename V::mapped_type>(item));
    return out;
  } else if constexpr (HasExactFields<V>) {
    return FromExactJson<V>(json);
  } else {
    return json.get<V>();
  }
}

}  // namespace exact_json_detail

template <HasExactFields T>
nlohmann::json ToExactJson(const T& value) {
  nlohmann::json json = nlohmann::json::object();
  std::apply(
      [&](const auto&... field) {
        ((json[field.name] = exact_json_detail::Write(value.*(field.member))), ...);
      },
      ExactFields(std::type_identity<T>{}));
  return json;
}

// Throws nlohmann::json exceptions for a missing field or a wrong type.
template <HasExactFields T>
T FromExactJson(const nlohmann::json& json) {
  T value{};
  std::apply(
      [&](const auto&... field) {
        ((value.*(field.member) =
              exact_json_detail::Read<std::remove_cvref_t<decltype(value.*(field.member))>>(
                  json.at(field.name))),
         ...);
      },
      ExactFields(std::type_identity<T>{}));
  return value;
}

}  // namespace mavloc
