#include "export/urdf/xml_source_edits.h"

#include <algorithm>
#include <stdexcept>

namespace mbx {

namespace {

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

}  // namespace

std::string xml_attribute_text(const std::string& value) {
    std::string s;
    for (char c : value) {
        if (c == '&') s += "&amp;";
        else if (c == '<') s += "&lt;";
        else if (c == '"') s += "&quot;";
        else s += c;
    }
    return s;
}

XmlSourceEdits::StartTag XmlSourceEdits::start_tag(const pugi::xml_node& e) const {
    // pugixml parsed these very bytes, so the tag is well-formed; the checks
    // only keep a caller's mismatched text from reading out of bounds.
    const auto broken = [] { throw std::logic_error("XmlSourceEdits: the node does not belong to this text"); };
    const ptrdiff_t offset = e.offset_debug();
    if (offset <= 0 || size_t(offset) >= text_.size() || text_[size_t(offset) - 1] != '<') broken();
    StartTag tag;
    size_t i = size_t(offset);
    const size_t n = text_.size();
    while (i < n && !blank(text_[i]) && text_[i] != '/' && text_[i] != '>') ++i;
    tag.name_end = i;
    for (;;) {
        while (i < n && blank(text_[i])) ++i;
        if (i >= n) broken();
        if (text_[i] == '/' || text_[i] == '>') {
            tag.close = i;
            tag.self_closing = text_[i] == '/';
            return tag;
        }
        Attribute a;
        const size_t name_begin = i;
        while (i < n && !blank(text_[i]) && text_[i] != '=') ++i;
        a.name.assign(text_.substr(name_begin, i - name_begin));
        while (i < n && blank(text_[i])) ++i;
        if (i >= n || text_[i] != '=') broken();
        ++i;
        while (i < n && blank(text_[i])) ++i;
        if (i >= n || (text_[i] != '"' && text_[i] != '\'')) broken();
        const char quote = text_[i++];
        a.value_begin = i;
        while (i < n && text_[i] != quote) ++i;
        if (i >= n) broken();
        a.value_end = i++;
        tag.attributes.push_back(std::move(a));
    }
}

std::string XmlSourceEdits::indent_before(size_t at) const {
    size_t b = at;
    while (b > 0 && (text_[b - 1] == ' ' || text_[b - 1] == '\t')) --b;
    if (b > 0 && text_[b - 1] != '\n') return {};  // not first on its line
    return std::string(text_.substr(b, at - b));
}

void XmlSourceEdits::set_attribute(const pugi::xml_node& e, const char* name, const std::string& value) {
    const StartTag tag = start_tag(e);
    for (const Attribute& a : tag.attributes)
        if (a.name == name) {
            edits_.push_back({a.value_begin, a.value_end - a.value_begin, xml_attribute_text(value), edits_.size()});
            return;
        }
    const size_t at = tag.attributes.empty() ? tag.name_end : tag.attributes.back().value_end + 1;
    edits_.push_back({at, 0, std::string(" ") + name + "=\"" + xml_attribute_text(value) + "\"", edits_.size()});
}

void XmlSourceEdits::insert_first_child(const pugi::xml_node& e, const std::string& element) {
    const StartTag tag = start_tag(e);
    const std::string newline = text_.find("\r\n") != std::string_view::npos ? "\r\n" : "\n";
    const std::string own = indent_before(size_t(e.offset_debug()) - 1);
    std::string child_indent = own + "  ";
    const pugi::xml_node first = e.find_child([](const pugi::xml_node& c) { return c.type() == pugi::node_element; });
    if (first && first.offset_debug() > 0) {
        const std::string s = indent_before(size_t(first.offset_debug()) - 1);
        if (!s.empty()) child_indent = s;
    }
    if (tag.self_closing) {
        edits_.push_back({tag.close, 2,
                          ">" + newline + child_indent + element + newline + own + "</" + e.name() + ">",
                          edits_.size()});
    } else if (first) {
        edits_.push_back({tag.close + 1, 0, newline + child_indent + element, edits_.size()});
    } else {
        edits_.push_back({tag.close + 1, 0, newline + child_indent + element + newline + own, edits_.size()});
    }
}

int XmlSourceEdits::line_of(const pugi::xml_node& e) const {
    const ptrdiff_t offset = e.offset_debug();
    if (offset < 0) return 0;
    const size_t end = std::min(size_t(offset), text_.size());
    return 1 + int(std::count(text_.begin(), text_.begin() + ptrdiff_t(end), '\n'));
}

std::string XmlSourceEdits::apply() const {
    std::vector<Edit> sorted = edits_;
    std::stable_sort(sorted.begin(), sorted.end(), [](const Edit& a, const Edit& b) { return a.at < b.at; });
    std::string out;
    out.reserve(text_.size() + 256 * sorted.size());
    size_t at = 0;
    for (const Edit& ed : sorted) {
        if (ed.at < at) throw std::logic_error("XmlSourceEdits: overlapping edits");
        out.append(text_.substr(at, ed.at - at));
        out += ed.insert;
        at = ed.at + ed.erase;
    }
    out.append(text_.substr(at));
    return out;
}

}  // namespace mbx
