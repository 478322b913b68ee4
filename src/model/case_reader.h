// Shared reading machinery of the case-file schemas (lumped fricrom-case-1 and FE
// fricrom-assembly-1): error context with file, key and line, numbers as expressions over the
// [parameters], and the sections both schemas share ([parameters], [analysis]).
#pragma once

#include <muParser.h>
#include <toml++/toml.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "fricrom/case_file.h"

namespace fricrom::detail {

// Error context: file name plus a key path like "contacts[2].theta" and the line of the node.
class Reader {
 public:
  Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void Fail(const std::string& key, const std::string& what,
                         const toml::node* node = nullptr) const {
    std::ostringstream s;
    s << source_;
    if (node && node->source().begin.line > 0) s << ":" << node->source().begin.line;
    s << ": key '" << key << "': " << what;
    throw CaseError(s.str());
  }

  void CheckKeys(const toml::table& t, const std::string& where,
                 const std::set<std::string>& allowed) const {
    for (const auto& [k, v] : t) {
      if (!allowed.count(std::string(k.str()))) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        Fail(where.empty() ? std::string(k.str()) : where + "." + std::string(k.str()),
             "unknown key (expected one of: " + list + ")", &v);
      }
    }
  }

  const toml::node& Require(const toml::table& t, const std::string& where,
                            const std::string& key) const {
    const toml::node* n = t.get(key);
    if (!n) Fail(Join(where, key), "missing (required)");
    return *n;
  }

  std::string String(const toml::table& t, const std::string& where, const std::string& key) const {
    const toml::node& n = Require(t, where, key);
    if (!n.is_string()) Fail(Join(where, key), "expected a string", &n);
    return std::string(*n.value<std::string>());
  }

  std::string StringOr(const toml::table& t, const std::string& where, const std::string& key,
                       const std::string& fallback) const {
    return t.get(key) ? String(t, where, key) : fallback;
  }

  // A number, or a string expression over the case parameters.
  double Number(const toml::node& n, const std::string& key) const {
    if (n.is_integer()) return static_cast<double>(*n.value<int64_t>());
    if (n.is_floating_point()) {
      const double v = *n.value<double>();
      if (!std::isfinite(v)) Fail(key, "expected a finite number", &n);
      return v;
    }
    if (n.is_string()) {
      const std::string expr(*n.value<std::string>());
      try {
        mu::Parser p;
        p.DefineConst("pi", std::numbers::pi);
        for (const auto& [name, value] : *parameters_) p.DefineConst(name, value);
        p.SetExpr(expr);
        const double v = p.Eval();
        if (!std::isfinite(v)) Fail(key, "expression '" + expr + "' is not finite", &n);
        return v;
      } catch (const mu::Parser::exception_type& e) {
        Fail(key,
             "cannot evaluate expression '" + expr + "': " + e.GetMsg() +
                 " (numbers, + - * / ^ ( ), functions and the [parameters] names are allowed)",
             &n);
      }
    }
    Fail(key, "expected a number or an expression string", &n);
  }

  double Number(const toml::table& t, const std::string& where, const std::string& key) const {
    return Number(Require(t, where, key), Join(where, key));
  }
  double NumberOr(const toml::table& t, const std::string& where, const std::string& key,
                  double fallback) const {
    const toml::node* n = t.get(key);
    return n ? Number(*n, Join(where, key)) : fallback;
  }
  double Positive(const toml::table& t, const std::string& where, const std::string& key) const {
    const double v = Number(t, where, key);
    if (!(v > 0.0)) Fail(Join(where, key), "expected a value > 0, got " + Fmt(v), t.get(key));
    return v;
  }
  double NonNegative(const toml::table& t, const std::string& where, const std::string& key) const {
    const double v = Number(t, where, key);
    if (!(v >= 0.0)) Fail(Join(where, key), "expected a value >= 0, got " + Fmt(v), t.get(key));
    return v;
  }
  double NonNegative(const toml::table& t, const std::string& where, const std::string& key,
                     double fallback) const {
    const double v = NumberOr(t, where, key, fallback);
    if (!(v >= 0.0)) Fail(Join(where, key), "expected a value >= 0, got " + Fmt(v), t.get(key));
    return v;
  }

  const toml::array& Array(const toml::table& t, const std::string& where,
                           const std::string& key) const {
    const toml::node& n = Require(t, where, key);
    if (!n.is_array()) Fail(Join(where, key), "expected an array", &n);
    return *n.as_array();
  }

  void SetParameters(const std::map<std::string, double>* p) { parameters_ = p; }
  static std::string Join(const std::string& where, const std::string& key) {
    return where.empty() ? key : where + "." + key;
  }
  static std::string Fmt(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
  }
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  const std::map<std::string, double>* parameters_ = nullptr;
};

inline const toml::table& TableAt(const Reader& rd, const toml::array& arr, size_t i,
                                  const std::string& where) {
  if (!arr[i].is_table()) rd.Fail(where, "expected a table ([[...]] entry)", &arr[i]);
  return *arr[i].as_table();
}

// [parameters] (plain numbers) with the --set overrides applied; rd then evaluates expressions
// over them. Also writes the resolved section.
void ParseParameters(Reader& rd, const toml::table& root,
                     const std::vector<ParameterOverride>& overrides, Case* cs,
                     toml::table* resolved);

// [analysis]; `loads` is checked against the harmonics (a load above H is an error).
void ParseAnalysis(const Reader& rd, const toml::table& root, const toml::array& loads,
                   size_t num_contacts, BalanceKind default_balance, AnalysisSettings* a,
                   toml::table* resolved);

// Validates the assembled model (CaseError naming cs->source) and stores the resolved TOML.
void FinishCase(const toml::table& resolved, Case* cs);

// The FE assembly schema (fricrom-assembly-1), after the TOML parse (assembly_file.cpp).
Case ParseAssembly(const toml::table& root, const std::string& source_name,
                   const std::vector<ParameterOverride>& overrides);

}  // namespace fricrom::detail
