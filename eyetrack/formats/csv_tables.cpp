#include "formats/csv_tables.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <opencv2/core.hpp>

#include "error.hpp"
#include "input_file.hpp"
#include "limits.hpp"

namespace gt::eyetrack {

std::string truthHeader() {
    return "frame,t_ms,cx,cy,axis_a,axis_b,angle_deg,visibility,yaw_deg,pitch_deg,target_x,target_"
           "y,gaze_x,gaze_y,"
           "phase,target_index,lid_open,eye_x_mm,eye_y_mm,eye_z_mm,gaze_dx,gaze_dy,gaze_dz,"
           "pupil_radius_mm,fix_x_mm,fix_y_mm,fix_z_mm";
}

std::string truthRow(const EyeTruth& t) {
    return cv::format(
        "%d,%.3f,%.4f,%.4f,%.4f,%.4f,%.3f,%.4f,%.4f,%.4f,%.2f,%.2f,%.2f,%.2f,%s,%d,%.3f,%.4f,%.4f,"
        "%.4f,%.6f,%.6f,%.6f,%.4f,%.2f,%.2f,%.2f",
        t.frame, t.tMs, t.centre.x, t.centre.y, t.axisA, t.axisB, t.angleDeg, t.visibility,
        t.yawDeg, t.pitchDeg, t.gaze.target.x, t.gaze.target.y, t.gaze.gaze.x, t.gaze.gaze.y,
        toString(t.gaze.phase), t.gaze.targetIndex, t.gaze.lidOpen, t.eyeCentreMm[0],
        t.eyeCentreMm[1], t.eyeCentreMm[2], t.gazeDirection[0], t.gazeDirection[1],
        t.gazeDirection[2], t.pupilRadiusMm, t.fixationMm[0], t.fixationMm[1], t.fixationMm[2]);
}

namespace {

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream in(line);
    while (std::getline(in, cell, ',')) {
        while (!cell.empty() && (cell.back() == '\r' || cell.back() == ' '))
            cell.pop_back();
        while (!cell.empty() && cell.front() == ' ')
            cell.erase(cell.begin());
        cells.push_back(cell);
    }
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    return cells;
}

} // namespace

CsvTable CsvTable::load(const std::filesystem::path& file,
                        const std::vector<std::string>& required) {
    // Read whole through the one input rule: a FIFO, a device or a runaway file is refused.
    std::istringstream in;
    try {
        in.str(io::readInputFile(file, io::limits::kTextTableBytes));
    } catch (const io::InputError& e) {
        throw FormatError(e.what());
    }
    CsvTable t;
    t.mFile = file.string();
    std::string line;
    if (!std::getline(in, line) || line.empty())
        throw FormatError(file.string() + ": empty (expected a header line)");
    const auto header = split(line);
    for (std::size_t i = 0; i < header.size(); ++i)
        t.mIndex[header[i]] = i;
    for (const auto& r : required)
        if (!t.mIndex.count(r))
            throw FormatError(file.string() + ": no '" + r + "' column in the header");
    int lineNo = 1;
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.empty() || line == "\r") continue;
        auto cells = split(line);
        if (cells.size() != header.size())
            throw FormatError(file.string() + ":" + std::to_string(lineNo) + ": " +
                              std::to_string(cells.size()) + " fields, the header has " +
                              std::to_string(header.size()));
        t.mRows.push_back(std::move(cells));
        t.mLines.push_back(lineNo);
    }
    return t;
}

const std::string& CsvTable::text(std::size_t row, const std::string& column) const {
    return mRows.at(row).at(mIndex.at(column));
}

std::string CsvTable::where(std::size_t row) const {
    return mFile + ":" + std::to_string(mLines.at(row));
}

void CsvTable::requireNumbers(const std::vector<std::string>& textColumns) const {
    for (const auto& [column, index] : mIndex) {
        if (std::find(textColumns.begin(), textColumns.end(), column) != textColumns.end())
            continue;
        for (std::size_t row = 0; row < mRows.size(); ++row)
            (void)number(row, column); // throws naming file, line and cell
    }
}

void CsvTable::requireIncreasing(const std::string& column) const {
    for (std::size_t row = 0; row < mRows.size(); ++row) {
        const double v = number(row, column);
        if (std::isnan(v)) throw FormatError(where(row) + ": " + column + " is empty");
        if (row > 0 && !(v > number(row - 1, column)))
            throw FormatError(where(row) + ": " + column + " " + text(row, column) +
                              " does not follow " + text(row - 1, column) +
                              " (rows must be in increasing " + column + ")");
    }
}

CsvTable CsvTable::loadTruth(const std::filesystem::path& file,
                             const std::vector<std::string>& required) {
    std::vector<std::string> columns = required;
    columns.emplace_back("frame");
    CsvTable t = load(file, columns);
    t.requireNumbers({"phase", "note"});
    t.requireIncreasing("frame");
    if (t.has("t_ms")) t.requireIncreasing("t_ms");
    // Frame numbers index frames: whole, and small enough to be exact as a double (a frame
    // 1e300 cast to an integer is undefined).
    constexpr double kMaxFrame = 9007199254740992.0; // 2^53
    for (std::size_t row = 0; row < t.rows(); ++row) {
        const double f = t.number(row, "frame");
        if (!(f >= 0.0 && f <= kMaxFrame) || f != std::floor(f))
            throw FormatError(t.where(row) + ": frame " + t.text(row, "frame") +
                              " is not a whole frame number");
    }
    return t;
}

double CsvTable::number(std::size_t row, const std::string& column) const {
    const std::string& s = text(row, column);
    if (s.empty()) return std::numeric_limits<double>::quiet_NaN();
    try {
        std::size_t used = 0;
        const double v = std::stod(s, &used);
        if (used == s.size() && std::isfinite(v)) return v;
    } catch (const std::exception&) {
    }
    throw FormatError(mFile + ":" + std::to_string(mLines[row]) + ": " + column + " '" + s +
                      "' is not a number");
}

} // namespace gt::eyetrack
