// One part of a PMXML file (a <Body>, <Ground> or <SimpleJoint>, found by
// pmxml_outline.h) parsed into a small tree reused from part to part, and
// PartNode, which reads it through the few pugi::xml_node calls the reader
// makes, so the reader's code is the same for both. Unlike pugixml's, its
// accessors are inline: walking the tree was as costly as parsing it when
// every name() was a call into the shared library.
//
// The subset is the outline's (plain UTF-8 elements, attributes and text;
// no references, comments, CDATA, instructions or carriage returns, no tab
// or line feed inside attribute values); parse_part returns false on
// anything else, and the reader then parses the whole file with pugixml.
#pragma once
#include <cstddef>
#include <cstring>
#include <string_view>
#include <vector>

#include "pmxml_outline.h"

namespace mbx_files {

struct PartTree {
    struct Element {
        const char* name = "";
        size_t name_length = 0;
        const char* text = "";  // the first text child that is not blank, "" if none
        std::ptrdiff_t offset = 0;  // of the name in the file
        int first_child = -1, next_sibling = -1;
        int subtree_end = 0;  // one past its last descendant (elements are in document order)
        int first_attribute = 0, attribute_count = 0;
    };
    struct Attribute {
        const char* name;
        const char* value;
    };
    std::vector<Element> elements;  // [0] the part
    std::vector<Attribute> attributes;
    std::vector<char> text;  // the part's text, names and values ended in place with NULs
};

// Parses `part` (one element, '<' to its end tag), which starts at byte
// `offset` of the file, into `tree`; false where pugixml must read the file.
// `conversions`: what the file holds (PmxmlOutline::conversions).
bool parse_part(std::string_view part, size_t offset, const xml_subset::Conversions& conversions, PartTree& tree);

class PartAttribute {
public:
    explicit PartAttribute(const char* value = nullptr) : value_(value) {}
    explicit operator bool() const { return value_ != nullptr; }
    const char* value() const { return value_ ? value_ : ""; }

private:
    const char* value_;
};

class PartNode {
public:
    PartNode() = default;
    PartNode(const PartTree* tree, int element) : tree_(tree), e_(element) {}

    explicit operator bool() const { return e_ >= 0; }
    bool operator!() const { return e_ < 0; }
    const char* name() const { return e_ < 0 ? "" : at().name; }
    const char* child_value() const { return e_ < 0 ? "" : at().text; }
    std::ptrdiff_t offset_debug() const { return e_ < 0 ? -1 : at().offset; }
    PartNode first_child() const { return e_ < 0 ? PartNode() : PartNode(tree_, at().first_child); }
    PartNode next_sibling() const { return e_ < 0 ? PartNode() : PartNode(tree_, at().next_sibling); }

    PartNode child(const char* name) const {
        for (PartNode c = first_child(); c; c = c.next_sibling())
            if (std::strcmp(c.name(), name) == 0) return c;
        return PartNode();
    }

    PartAttribute attribute(const char* name) const {
        if (e_ < 0) return PartAttribute();
        const PartTree::Element& el = at();
        for (int i = 0; i < el.attribute_count; ++i) {
            const PartTree::Attribute& a = tree_->attributes[size_t(el.first_attribute + i)];
            if (std::strcmp(a.name, name) == 0) return PartAttribute(a.value);
        }
        return PartAttribute();
    }

    // The first descendant, in document order, for which `pred` holds.
    template <class Pred>
    PartNode find_node(Pred pred) const {
        if (e_ < 0) return PartNode();
        for (int d = e_ + 1; d < at().subtree_end; ++d)
            if (pred(PartNode(tree_, d))) return PartNode(tree_, d);
        return PartNode();
    }

    // The children named `name`, for range-for.
    class Named;
    Named children(const char* name) const;

private:
    const PartTree::Element& at() const { return tree_->elements[size_t(e_)]; }
    const PartTree* tree_ = nullptr;
    int e_ = -1;
};

// The children of a node named `name`, for range-for.
class PartNode::Named {
public:
    class iterator {
    public:
        iterator(PartNode n, const char* name) : n_(n), name_(name) { skip(); }
        PartNode operator*() const { return n_; }
        iterator& operator++() {
            n_ = n_.next_sibling();
            skip();
            return *this;
        }
        bool operator!=(const iterator& o) const { return n_.e_ != o.n_.e_; }

    private:
        void skip() {
            while (n_ && std::strcmp(n_.name(), name_) != 0) n_ = n_.next_sibling();
        }
        PartNode n_;
        const char* name_;
    };
    Named(PartNode parent, const char* name) : parent_(parent), name_(name) {}
    iterator begin() const { return iterator(parent_.first_child(), name_); }
    iterator end() const { return iterator(PartNode(), name_); }

private:
    PartNode parent_;
    const char* name_;
};

inline PartNode::Named PartNode::children(const char* name) const { return Named(*this, name); }

}  // namespace mbx_files
