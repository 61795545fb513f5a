#include "core/csv_table.h"

#include <charconv>
#include <cmath>
#include <sstream>
#include <string_view>

#include "core/heartbeat.h"
#include "core/input_file.h"

namespace mbx {

namespace {

[[noreturn]] void fail(const Subject& subject, const std::string& path, int line, const std::string& message) {
    throw Error(MBX_ERROR_INVALID_INPUT, subject, path + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + message,
                path, line);
}

// Header names lose surrounding blanks and quotes (spreadsheets quote them).
std::string trim(const std::string& s) {
    size_t a = 0, b = s.size();
    while (a < b && (s[a] == ' ' || s[a] == '\t' || s[a] == '"')) ++a;
    while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t' || s[b - 1] == '\r' || s[b - 1] == '"')) --b;
    return s.substr(a, b - a);
}

}  // namespace

int CsvTable::column(const std::string& name) const {
    for (size_t k = 0; k < header.size(); ++k)
        if (header[k] == name) return int(k);
    return -1;
}

CsvTable read_csv_table(const std::string& path, const Subject& subject) {
    std::string text, why;
    if (!read_input_file(path, text, why)) throw Error(MBX_ERROR_IO, subject, "cannot read the record '" + path + "': " + why, path);
    return read_csv_table_text(text, path, subject);
}

CsvTable read_csv_table_text(const std::string& text, const std::string& path, const Subject& subject) {
    // Spreadsheets save "CSV UTF-8" with a byte-order mark before the first column's name.
    // Lines are views into the text: a record of millions of rows is not
    // copied line by line (nor whole, into a stream).
    size_t at = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
    auto next_line = [&](std::string_view& line) {
        if (at >= text.size()) return false;
        size_t end = text.find('\n', at);
        if (end == std::string::npos) end = text.size();
        line = std::string_view(text).substr(at, end - at);
        at = end + 1;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        return true;
    };
    CsvTable t;
    std::string_view line;
    if (!next_line(line))
        fail(subject, path, 1, "the record is empty (a header line of column names is expected)");
    {
        std::stringstream header{std::string(line)};
        std::string cell;
        while (std::getline(header, cell, ',')) t.header.push_back(trim(cell));
    }
    t.columns.assign(t.header.size(), {});
    int number = 1;
    while (next_line(line)) {
        heartbeat();
        ++number;
        if (line.find_first_not_of(" \t") == std::string_view::npos) continue;
        const char* p = line.data();
        const char* end = p + line.size();
        for (size_t c = 0; c < t.header.size(); ++c) {
            while (p < end && (*p == ' ' || *p == '\t')) ++p;
            if (p < end && *p == '+') ++p;  // from_chars takes no plus sign
            double v = 0;
            const auto r = std::from_chars(p, end, v);
            if (r.ec != std::errc() || !std::isfinite(v))
                fail(subject, path, number, "column '" + t.header[c] + "' is not a finite number");
            p = r.ptr;
            while (p < end && (*p == ' ' || *p == '\t')) ++p;
            if (c + 1 < t.header.size()) {
                if (p >= end || *p != ',')
                    fail(subject, path, number, "expected " + std::to_string(t.header.size()) + " comma-separated values");
                ++p;
            } else if (p != end) {
                fail(subject, path, number, "more values than the header's " + std::to_string(t.header.size()) + " columns");
            }
            t.columns[c].push_back(v);
        }
    }
    return t;
}

}  // namespace mbx
