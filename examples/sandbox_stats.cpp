#include "sandbox_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numeric>

namespace sandbox {

Summary summarise(std::vector<double> values) {
    Summary s;
    s.count = values.size();
    if (values.empty()) return s;
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    auto rank = [&](double q) { return values[std::min(n - 1, size_t(std::max(1.0, std::ceil(q * double(n)))) - 1)]; };
    s.mean = std::accumulate(values.begin(), values.end(), 0.0) / double(n);
    s.median = rank(0.5);
    s.p95 = rank(0.95);
    s.max = values.back();
    return s;
}

std::vector<double> column(const std::vector<FrameSample>& samples, size_t first, double FrameSample::*field) {
    std::vector<double> out;
    for (size_t k = first; k < samples.size(); ++k) out.push_back(samples[k].*field);
    return out;
}

void Window::add(const FrameSample& s) {
    simMs += s.simMs;
    impactsMs += s.impactsMs;
    contactsMs += s.contactsMs;
    renderMs += s.renderMs;
    frameMs += s.frameMs;
    simMaxMs = std::max(simMaxMs, s.simMs);
    ++frames;
}

std::string hostCpuName() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("model name", 0) == 0) {
            const size_t colon = line.find(':');
            if (colon != std::string::npos) {
                const size_t start = line.find_first_not_of(" \t", colon + 1);
                if (start != std::string::npos) return line.substr(start);
            }
        }
    }
    return "unknown";
}

std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\t':
                out += "\\t";
                break;
            case '\r':
                out += "\\r";
                break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", c);
                    out += buf;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

JsonObject& JsonObject::add(const std::string& key, const std::string& value) {
    m_fields.emplace_back(key, jsonString(value));
    return *this;
}

JsonObject& JsonObject::add(const std::string& key, double value) {
    if (!std::isfinite(value)) return addNull(key);
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.6g", value);
    m_fields.emplace_back(key, buf);
    return *this;
}

JsonObject& JsonObject::add(const std::string& key, int64_t value) {
    m_fields.emplace_back(key, std::to_string(value));
    return *this;
}

JsonObject& JsonObject::add(const std::string& key, bool value) {
    m_fields.emplace_back(key, value ? "true" : "false");
    return *this;
}

JsonObject& JsonObject::addNull(const std::string& key) {
    m_fields.emplace_back(key, "null");
    return *this;
}

JsonObject& JsonObject::add(const std::string& key, const Summary& s) {
    JsonObject o;
    if (s.count == 0) {  // no samples: no figures (null), rather than zeros that read as measured
        o.addNull("mean").addNull("median").addNull("p95").addNull("max").add("count", int64_t(0));
        m_fields.emplace_back(key, o.text());
        return *this;
    }
    o.add("mean", s.mean).add("median", s.median).add("p95", s.p95).add("max", s.max).add("count", int64_t(s.count));
    m_fields.emplace_back(key, o.text());
    return *this;
}

JsonObject& JsonObject::add(const std::string& key, const std::vector<double>& values) {
    std::string text = "[";
    char number[32];
    for (size_t k = 0; k < values.size(); ++k) {
        std::snprintf(number, sizeof number, "%s%.3f", k == 0 ? "" : ",", std::isfinite(values[k]) ? values[k] : 0.0);
        text += number;
    }
    m_fields.emplace_back(key, text + "]");
    return *this;
}

std::string JsonObject::text(bool multiline) const {
    std::string out = "{";
    for (size_t k = 0; k < m_fields.size(); ++k) {
        out += std::string(k ? "," : "") +
               (multiline ? "\n  "
                : k       ? " "
                          : "") +
               jsonString(m_fields[k].first) + ": " + m_fields[k].second;
    }
    return out + (multiline ? "\n}" : "}");
}

}  // namespace sandbox
