#include "vrml_inline_paths.h"
#include "host_adapters/common/text.h"

#include <cctype>
#include <filesystem>
#include <system_error>

namespace fs = std::filesystem;

namespace mbx_files::vrml {
namespace {

// A directory with more entries than this is matched by exact name only.
constexpr size_t max_listing = 100000;

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

std::string percent_decode(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() && hex_digit(s[i + 1]) >= 0 && hex_digit(s[i + 2]) >= 0) {
            out += static_cast<char>(hex_digit(s[i + 1]) * 16 + hex_digit(s[i + 2]));
            i += 2;
        } else {
            out += s[i];
        }
    }
    return out;
}

bool is_file(const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec);
}

// The local path `url` names, "" for none; `remote` set for other schemes.
std::string local_part(const std::string& url, bool& remote) {
    remote = false;
    std::string s = url;
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.erase(s.begin());
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
    if (const size_t hash = s.find('#'); hash != std::string::npos) s.erase(hash);

    // A scheme is two or more letters before ':' (one letter is a Windows drive).
    const size_t colon = s.find(':');
    bool has_scheme = colon != std::string::npos && colon >= 2;
    for (size_t i = 0; has_scheme && i < colon; ++i)
        if (!std::isalpha(static_cast<unsigned char>(s[i])) && s[i] != '+' && s[i] != '-' && s[i] != '.')
            has_scheme = false;
    if (has_scheme) {
        if (lower_case(s.substr(0, colon)) != "file") {
            remote = true;
            return {};
        }
        s.erase(0, colon + 1);
        if (s.rfind("//", 0) == 0) {
            s.erase(0, 2);  // authority: "" or "localhost"
            const size_t slash = s.find('/');
            s = slash == std::string::npos ? std::string() : s.substr(slash);
        }
    }
    s = percent_decode(s);
    for (char& c : s)
        if (c == '\\') c = '/';
    return s;
}

}  // namespace

InlineUrl InlineResolver::resolve(const std::string& url, const std::string& including_file) {
    const fs::path base = fs::path(including_file).parent_path();
    const std::string key = base.string() + '\n' + url;
    if (auto it = answers_.find(key); it != answers_.end()) return it->second;

    InlineUrl out;
    bool remote = false;
    const std::string local = local_part(url, remote);
    if (remote) {
        out.status = InlineUrl::Status::remote;
        out.path = url;
    } else if (!local.empty()) {
        const fs::path target(local);
        const fs::path full = target.is_absolute() ? target : base / target;
        out.path = full.lexically_normal().string();
        if (is_file(full)) {
            out.status = InlineUrl::Status::found;
        } else {
            const std::string root =
                target.is_absolute() ? target.root_path().string() : (base.empty() ? std::string(".") : base.string());
            const std::string rel = target.is_absolute() ? target.relative_path().string() : local;
            const std::string found = find_ignoring_case(root, rel);
            if (!found.empty() && is_file(found)) {
                out.status = InlineUrl::Status::found;
                out.path = fs::path(found).lexically_normal().string();
            }
        }
    }
    answers_[key] = out;
    return out;
}

const std::unordered_map<std::string, std::string>& InlineResolver::listing(const std::string& dir) {
    auto [it, fresh] = listings_.try_emplace(dir);
    if (fresh) {
        std::error_code ec;
        for (fs::directory_iterator d(dir, ec), end; !ec && d != end && it->second.size() < max_listing;
             d.increment(ec)) {
            const std::string name = d->path().filename().string();
            it->second.emplace(lower_case(name), name);
        }
    }
    return it->second;
}

// Walks `relative` from `base`, matching each component case-insensitively
// when the exact name is missing. "" if some component has no match.
std::string InlineResolver::find_ignoring_case(const std::string& base, const std::string& relative) {
    fs::path at = base;
    for (const fs::path& part : fs::path(relative)) {
        const std::string name = part.string();
        if (name.empty() || name == ".") continue;
        std::error_code ec;
        if (name == ".." || fs::exists(at / part, ec)) {
            at /= part;
            continue;
        }
        const auto& entries = listing(at.lexically_normal().string());
        const auto match = entries.find(lower_case(name));
        if (match == entries.end()) return {};
        at /= match->second;
    }
    return at.string();
}

}  // namespace mbx_files::vrml
