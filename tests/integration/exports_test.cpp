// The shared library exports only the C API (mbx.h: "exports only symbols
// that begin with mbx_"). Read from the ELF dynamic symbol table directly,
// and cross-checked with `nm -D --defined-only` when nm is installed.
#include <doctest/doctest.h>

#include <elf.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/plugin_fixture.h"
#include "tests/common/skip.h"

namespace MBX_UNITY_ID {

using namespace itest;

namespace {

bool read_all(const char* path, std::vector<char>& out) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return true;
}

// Names of the global/weak symbols the library defines in .dynsym (64-bit ELF).
std::set<std::string> defined_dynamic_symbols(const std::vector<char>& file) {
    std::set<std::string> names;
    REQUIRE(file.size() >= sizeof(Elf64_Ehdr));
    Elf64_Ehdr eh;
    std::memcpy(&eh, file.data(), sizeof eh);
    REQUIRE(std::memcmp(eh.e_ident, ELFMAG, SELFMAG) == 0);
    REQUIRE(eh.e_ident[EI_CLASS] == ELFCLASS64);
    REQUIRE(eh.e_shoff + size_t(eh.e_shnum) * sizeof(Elf64_Shdr) <= file.size());
    std::vector<Elf64_Shdr> sections(eh.e_shnum);
    std::memcpy(sections.data(), file.data() + eh.e_shoff, sections.size() * sizeof(Elf64_Shdr));
    for (const Elf64_Shdr& s : sections) {
        if (s.sh_type != SHT_DYNSYM) continue;
        REQUIRE(s.sh_link < sections.size());
        const Elf64_Shdr& strtab = sections[s.sh_link];
        REQUIRE(s.sh_offset + s.sh_size <= file.size());
        REQUIRE(strtab.sh_offset + strtab.sh_size <= file.size());
        for (size_t off = 0; off + sizeof(Elf64_Sym) <= s.sh_size; off += sizeof(Elf64_Sym)) {
            Elf64_Sym sym;
            std::memcpy(&sym, file.data() + s.sh_offset + off, sizeof sym);
            const unsigned bind = ELF64_ST_BIND(sym.st_info);
            if (sym.st_shndx == SHN_UNDEF || (bind != STB_GLOBAL && bind != STB_WEAK)) continue;
            REQUIRE(sym.st_name < strtab.sh_size);
            names.insert(std::string(file.data() + strtab.sh_offset + sym.st_name));
        }
    }
    return names;
}

}  // namespace

TEST_CASE("exports: the shared library exports only mbx_ symbols") {
    std::vector<char> file;
    REQUIRE_MESSAGE(read_all(plugin_path(), file), "cannot read " << plugin_path());
    const std::set<std::string> names = defined_dynamic_symbols(file);
    CHECK(names.count("mbx_plugin_api") == 1);
    CHECK(names.count("mbx_translate") == 1);
    CHECK(names.count("mbx_version") == 1);
    for (const std::string& n : names) CHECK_MESSAGE(n.rfind("mbx_", 0) == 0, "unexpected export: " << n);

    // Cross-check with nm, when present.
    const std::string command = std::string("nm -D --defined-only '") + plugin_path() + "' 2>/dev/null";
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) {
        MBX_SKIP("popen failed: the nm cross-check did not run");
    }
    std::set<std::string> from_nm;
    char line[1024];
    while (std::fgets(line, sizeof line, pipe)) {
        std::istringstream fields(line);
        std::string address, type, name;
        if (!(fields >> address >> type >> name)) continue;
        from_nm.insert(name.substr(0, name.find('@')));
    }
    const int rc = pclose(pipe);
    if (rc != 0 || from_nm.empty()) {
        MBX_SKIP("nm not available: checked the ELF dynamic symbol table only");
    }
    CHECK(from_nm == names);
}
}  // namespace MBX_UNITY_ID
