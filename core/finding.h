// Findings (what validation reports) and the internal error type (what stops a
// translation). Both name their subject so a user can find it in the CAD.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

#include "mbx/mbx.h"

namespace mbx {

struct Subject {
    mbx_subject_kind kind = MBX_SUBJECT_NONE;
    std::string id;
    std::string name;

    static Subject body(std::string id, std::string name) { return {MBX_SUBJECT_BODY, std::move(id), std::move(name)}; }
    static Subject frame(std::string id, std::string name) { return {MBX_SUBJECT_FRAME, std::move(id), std::move(name)}; }
    static Subject constraint(std::string id, std::string name) {
        return {MBX_SUBJECT_CONSTRAINT, std::move(id), std::move(name)};
    }
    static Subject rigid_body(std::string id, std::string name) {
        return {MBX_SUBJECT_RIGID_BODY, std::move(id), std::move(name)};
    }
    static Subject loop(std::string id) { return {MBX_SUBJECT_LOOP, std::move(id), {}}; }
    static Subject model(std::string name) { return {MBX_SUBJECT_MODEL, {}, std::move(name)}; }
};

struct Finding {
    mbx_severity severity = MBX_SEVERITY_WARNING;
    mbx_finding_code code = MBX_FINDING_HOST_STATUS;
    Subject subject;
    std::string message;
    std::string code_text;  // host's own code for MBX_FINDING_HOST_DIAGNOSTIC, else ""
    std::string file;       // input file the finding is about, "" if none
    int line = 0;

    const char* code_name() const;
};

using Findings = std::vector<Finding>;

// Short, stable name of a code ("inertia_not_positive_definite").
const char* finding_code_name(mbx_finding_code code);
const char* severity_name(mbx_severity severity);
const char* subject_kind_name(mbx_subject_kind kind);

// Thrown inside the SDK only; the C API turns it into a status and message.
class Error : public std::runtime_error {
public:
    Error(mbx_status status, Subject subject, const std::string& message, std::string file = {}, int line = 0)
        : std::runtime_error(message), status_(status), subject_(std::move(subject)), file_(std::move(file)),
          line_(line) {}
    mbx_status status() const { return status_; }
    const Subject& subject() const { return subject_; }
    const std::string& file() const { return file_; }
    int line() const { return line_; }

private:
    mbx_status status_;
    Subject subject_;
    std::string file_;
    int line_;
};

}  // namespace mbx
