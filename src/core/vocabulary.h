// The names a user spells out for each choice: integrator method, precision, backend, thermostat
// kind, cutoff shift and placement. One table per choice, read by the command line, scene files,
// scripts and the panel, so that a name is accepted, listed and printed the same way everywhere.
//
// Design note. A table is a static array of terms (value, name, note); parsing, naming, the list in
// help texts and the "unknown ..." message all come from it, so a new method is one line in
// vocabulary.cpp. Method and CutoffShift are defined in kernels/ (the device code switches on
// them); the enums only the host uses are declared here rather than in scene.h so that scene.h can
// include this header without a cycle. The display choices (colour mode, frame size) belong to the
// app, which has their tables (src/app/display_vocabulary.h) built on the same Vocabulary.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "butcher_tableau.h"  // Method
#include "corebox/types.h"    // Precision, BackendKind, Exchange: shared with the public API
#include "pair_potential.h"   // CutoffShift

namespace corebox {

enum class ThermostatKind { Bussi, Rescale, None };
enum class Placement { Lattice, Random };
// How pair forces are summed (DESIGN.md sec. 2): a scene asks for auto, all_pairs or
// neighbour_list; the resolved model (force_model.h) is AllPairs, NeighbourList or None (no pair
// force at all: every epsilon is 0).
enum class ForceModel { Auto, AllPairs, NeighbourList, None };

template <class Enum>
struct Term {
    Enum value;
    const char* name;  // as written in scene files, on the command line and in scripts
    const char* note;  // shown beside the name where there is room (the panel): "order 4"; or ""
};

template <class Enum>
class Vocabulary {
public:
    // `what` names the choice in messages: "unknown <what> 'x'".
    template <size_t N>
    constexpr Vocabulary(const char* what, const Term<Enum> (&terms)[N]) : m_what(what), m_terms(terms), m_count(N) {}

    const char* what() const { return m_what; }
    const Term<Enum>* begin() const { return m_terms; }
    const Term<Enum>* end() const { return m_terms + m_count; }
    size_t size() const { return m_count; }

    // Position in the table (for a combo box), or size() for a value the table lacks.
    size_t indexOf(Enum value) const {
        for (size_t i = 0; i < m_count; ++i) {
            if (m_terms[i].value == value) return i;
        }
        return m_count;
    }
    const char* name(Enum value) const {
        const size_t i = indexOf(value);
        return i < m_count ? m_terms[i].name : "?";
    }
    bool parse(const std::string& text, Enum* value) const {
        for (const Term<Enum>& term : *this) {
            if (text == term.name) {
                *value = term.value;
                return true;
            }
        }
        return false;
    }
    std::vector<std::string> names() const {
        std::vector<std::string> out;
        for (const Term<Enum>& term : *this) out.emplace_back(term.name);
        return out;
    }
    // "euler, rk2, rk4": for help texts and messages.
    std::string list() const {
        std::string out;
        for (const Term<Enum>& term : *this) out += (out.empty() ? "" : ", ") + std::string(term.name);
        return out;
    }
    // "unknown method 'rk5'; one of: euler, rk2, ...": the same wording wherever a name is read.
    std::string unknown(const std::string& text) const {
        return "unknown " + std::string(m_what) + " '" + text + "'; one of: " + list();
    }

private:
    const char* m_what;
    const Term<Enum>* m_terms;
    size_t m_count;
};

const Vocabulary<Method>& methodTable();
const Vocabulary<Precision>& precisionTable();
const Vocabulary<BackendKind>& backendTable();
const Vocabulary<ThermostatKind>& thermostatTable();
const Vocabulary<CutoffShift>& shiftTable();
const Vocabulary<Placement>& placementTable();
const Vocabulary<Exchange>& exchangeTable();
const Vocabulary<ForceModel>& forceModelTable();  // the scene's choices; forceModelName also names None

// Shorthands for the tables above, kept for their many callers.
const char* methodName(Method method);
bool parseMethod(const std::string& text, Method* method);
const char* precisionName(Precision precision);
const char* thermostatName(ThermostatKind kind);
const char* shiftName(CutoffShift shift);
const char* exchangeName(Exchange exchange);
const char* forceModelName(ForceModel model);

}  // namespace corebox
