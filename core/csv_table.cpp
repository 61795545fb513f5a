#include "core/csv_table.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
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

namespace {

// Parses the text as it comes, in pieces of any size: a record of gigabytes
// is never held whole, only its numbers. Lines are views into the piece (one
// split across pieces is carried over).
class CsvReader {
public:
    CsvReader(const std::string& path, const Subject& subject, uint64_t total)
        : path_(path), subject_(subject), total_(double(std::max<uint64_t>(total, 1))) {}

    void feed(std::string_view piece) {
        size_t at = 0;
        if (!carry_.empty()) {
            const size_t end = piece.find('\n');
            if (end == std::string_view::npos) return carry_.append(piece), void();
            carry_.append(piece.substr(0, end));
            line(carry_);
            carry_.clear();
            at = end + 1;
        }
        for (size_t end; (end = piece.find('\n', at)) != std::string_view::npos; at = end + 1)
            line(piece.substr(at, end - at));
        carry_.assign(piece.substr(at));
    }

    CsvTable finish() {
        if (!carry_.empty()) line(carry_);
        if (number_ == 0) fail(subject_, path_, 1, "the record is empty (a header line of column names is expected)");
        return std::move(t_);
    }

private:
    void line(std::string_view text) {
        consumed_ += double(text.size() + 1);
        ++number_;
        if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
        if (number_ == 1) return header(text);
        heartbeat(consumed_ / total_);
        if (text.find_first_not_of(" \t") == std::string_view::npos) return;
        const char* p = text.data();
        const char* end = p + text.size();
        const size_t n = t_.header.size();
        for (size_t c = 0; c < n; ++c) {
            while (p < end && (*p == ' ' || *p == '\t')) ++p;
            if (p < end && *p == '+') ++p;  // from_chars takes no plus sign
            double v = 0;
            const auto r = std::from_chars(p, end, v);
            if (r.ec != std::errc() || !std::isfinite(v))
                fail(subject_, path_, number_, "column '" + t_.header[c] + "' is not a finite number");
            p = r.ptr;
            while (p < end && (*p == ' ' || *p == '\t')) ++p;
            if (c + 1 < n) {
                if (p >= end || *p != ',') fail(subject_, path_, number_, "expected " + std::to_string(n) + " comma-separated values");
                ++p;
            } else if (p != end) {
                fail(subject_, path_, number_, "more values than the header's " + std::to_string(n) + " columns");
            }
            t_.columns[c].push_back(v);
        }
    }

    void header(std::string_view text) {
        // Spreadsheets save "CSV UTF-8" with a byte-order mark before the first column's name.
        if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
        std::stringstream names{std::string(text)};
        std::string cell;
        while (std::getline(names, cell, ',')) t_.header.push_back(trim(cell));
        t_.columns.assign(t_.header.size(), {});
    }

    const std::string& path_;
    const Subject& subject_;
    double total_, consumed_ = 0;
    int number_ = 0;
    std::string carry_;
    CsvTable t_;
};

}  // namespace

CsvTable read_csv_table(const std::string& path, const Subject& subject) {
    uint64_t size = 0;
    std::string why = input_file_problem(path, &size);
    CsvReader reader(path, subject, size);
    if (why.empty() && read_input_pieces(path, [&](std::string_view piece) { reader.feed(piece); }, why)) return reader.finish();
    throw Error(MBX_ERROR_IO, subject, "cannot read the record '" + path + "': " + why, path);
}

CsvTable read_csv_table_text(const std::string& text, const std::string& path, const Subject& subject) {
    CsvReader reader(path, subject, text.size());
    reader.feed(text);
    return reader.finish();
}

}  // namespace mbx
