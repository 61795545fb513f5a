// A numeric CSV table: a header line of column names, then rows of finite
// numbers separated by commas. The one reader of that format, shared by
// calibration's records and the view's trajectories, so both refuse the same
// bad files with the same words.
#pragma once
#include <string>
#include <vector>

#include "core/finding.h"

namespace mbx {

struct CsvTable {
    std::vector<std::string> header;
    std::vector<std::vector<double>> columns;  // one per header name, a value per row
    int column(const std::string& name) const;  // its index, or -1
};

// Reads `path`. Throws mbx::Error (subject `subject`, naming the file and the
// line): a file that cannot be read, no header, a cell that is not a finite
// number, too few or too many values on a line. Blank lines are skipped.
CsvTable read_csv_table(const std::string& path, const Subject& subject);
// The same from text in memory; `path` names it in errors.
CsvTable read_csv_table_text(const std::string& text, const std::string& path, const Subject& subject);

}  // namespace mbx
