// mbx_stub_host: plays the CAD system. Loads the mbx plugin at run time (it
// is deliberately not linked), serves a stub assembly through the host
// callback table, translates it, prints the summary and writes the report.
//
// Exit status: 0 success, 1 the SDK reported a failure (its message is on
// stderr), 2 bad usage or a plugin that cannot be loaded.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "assemblies/stub_assembly.h"
#include "loader/plugin_loader.h"

namespace {

const char kUsage[] =
    "usage: mbx_stub_host --plugin <libmbx.so> --assembly <name> -o <dir>\n"
    "                     [--fail-at-body K] [--nan-at-body K] [--fail-at-constraint K] [--v1-host]\n"
    "       mbx_stub_host --list\n"
    "  <name> is a builtin (see --list) or generated:<bodies>[:<seed>]\n";

struct Options {
    std::string plugin, assembly, output;
    mbx_stub::Faults faults;
    bool v1_host = false;
    bool list = false;
};

bool parse_index(const char* text, long& out) {
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (!*text || *end || v < 0) return false;
    out = v;
    return true;
}

bool parse(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool has_value = i + 1 < argc;
        if (arg == "--v1-host") {
            o.v1_host = true;
        } else if (arg == "--list") {
            o.list = true;
        } else if (arg == "--plugin" && has_value) {
            o.plugin = argv[++i];
        } else if (arg == "--assembly" && has_value) {
            o.assembly = argv[++i];
        } else if ((arg == "-o" || arg == "--output") && has_value) {
            o.output = argv[++i];
        } else if (arg == "--fail-at-body" && has_value) {
            if (!parse_index(argv[++i], o.faults.fail_at_body)) return false;
        } else if (arg == "--nan-at-body" && has_value) {
            if (!parse_index(argv[++i], o.faults.nan_at_body)) return false;
        } else if (arg == "--fail-at-constraint" && has_value) {
            if (!parse_index(argv[++i], o.faults.fail_at_constraint)) return false;
        } else {
            return false;
        }
    }
    return o.list || (!o.plugin.empty() && !o.assembly.empty() && !o.output.empty());
}

bool make_assembly(const std::string& name, mbx_stub::Assembly& out) {
    const std::string prefix = "generated:";
    if (name.compare(0, prefix.size(), prefix) != 0) return mbx_stub::builtin_assembly(name, out);
    const char* text = name.c_str() + prefix.size();
    char* end = nullptr;
    const unsigned long bodies = std::strtoul(text, &end, 10);
    if (end == text) return false;
    unsigned long seed = 1;
    if (*end == ':') {
        const char* seed_text = end + 1;
        seed = std::strtoul(seed_text, &end, 10);
        if (end == seed_text) return false;
    }
    if (*end) return false;
    out = mbx_stub::generate_assembly(bodies, uint32_t(seed));
    return true;
}

void print_summary(const mbx_mechanism_summary& s) {
    std::printf("parts: %u\n", s.part_count);
    std::printf("rigid bodies: %u\n", s.rigid_body_count);
    std::printf("joint nodes: %u\n", s.joint_node_count);
    std::printf("joints: %u (revolute %u, prismatic %u, spherical %u)\n", s.joint_count, s.revolute_count,
                s.prismatic_count, s.spherical_count);
    std::printf("welds merged: %u\n", s.weld_count);
    std::printf("loops: %u (planar %u, cut joints %u, collapsed weld loops %u)\n", s.loop_count,
                s.planar_loop_count, s.cut_joint_count, s.collapsed_weld_loop_count);
    std::printf("dof: %d (Gruebler %d, redundant constraints %u, floating bodies %u)\n", s.dof, s.gruebler_dof,
                s.redundant_constraint_count, s.floating_body_count);
    std::printf("findings: %u warnings, %u errors\n", s.warning_count, s.error_count);
}

// Releases the SDK objects whatever path main takes.
struct Session {
    const mbx_api* api = nullptr;
    mbx_context* context = nullptr;
    mbx_mechanism* mechanism = nullptr;
    ~Session() {
        if (mechanism) api->mechanism_destroy(mechanism);
        if (context) api->context_destroy(context);
    }
};

int sdk_failure(const Session& s, const char* what, mbx_status status) {
    const char* message = s.context ? s.api->context_last_error(s.context) : "";
    std::fprintf(stderr, "mbx_stub_host: %s failed (%s): %s\n", what, s.api->status_name(status),
                 message && *message ? message : "(no message)");
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    if (!parse(argc, argv, o)) {
        std::fputs(kUsage, stderr);
        return 2;
    }
    if (o.list) {
        for (const std::string& name : mbx_stub::builtin_names()) std::printf("%s\n", name.c_str());
        return 0;
    }
    mbx_stub::Assembly assembly;
    if (!make_assembly(o.assembly, assembly)) {
        std::fprintf(stderr, "mbx_stub_host: unknown assembly '%s' (try --list)\n", o.assembly.c_str());
        return 2;
    }

    mbx_stub::Plugin plugin;
    std::string error;
    if (!plugin.load(o.plugin, &error)) {
        std::fprintf(stderr, "mbx_stub_host: %s\n", error.c_str());
        return 2;
    }
    const mbx_api* api = plugin.api();
    std::printf("plugin: mbx %s (ABI %u)\n", api->version(), plugin.abi_version());
    std::printf("assembly: %s%s\n", assembly.name.c_str(), o.v1_host ? " (served by a version-1 host)" : "");

    // The host must outlive the mechanism (it may still be asked for shapes),
    // so it is declared before the session.
    const mbx_stub::Host host(std::move(assembly), o.faults);
    Session s;
    s.api = api;
    mbx_status status = api->context_create(&s.context);
    if (status != MBX_OK) return sdk_failure(s, "creating a context", status);

    status = api->translate(s.context, o.v1_host ? host.v1_table() : host.table(), nullptr, &s.mechanism);
    if (status != MBX_OK) return sdk_failure(s, "translation", status);

    mbx_mechanism_summary summary{};
    summary.struct_size = sizeof summary;
    status = api->mechanism_get_summary(s.mechanism, &summary);
    if (status != MBX_OK) return sdk_failure(s, "reading the summary", status);
    print_summary(summary);

    status = api->mechanism_write_report(s.context, s.mechanism, o.output.c_str());
    if (status != MBX_OK) return sdk_failure(s, "writing the report", status);
    std::printf("report: %s/report.json, %s/report.txt\n", o.output.c_str(), o.output.c_str());
    return 0;
}
