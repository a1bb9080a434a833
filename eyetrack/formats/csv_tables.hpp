#pragma once
// The tracker's CSV files.
//  truth (eyesim): frame,t_ms,cx,cy,axis_a,axis_b,angle_deg,visibility,yaw_deg,pitch_deg,
//                  target_x,target_y,gaze_x,gaze_y,phase,target_index,lid_open,
//                  eye_x_mm,eye_y_mm,eye_z_mm,gaze_dx,gaze_dy,gaze_dz,pupil_radius_mm (camera
//                  frame), fix_x_mm,fix_y_mm,fix_z_mm (the fixated point, display frame)
//  pupils (track --pupils): frame,t_ms,cx,cy,axis_a,axis_b,angle_deg,confidence
//  gaze (track --out): t_ms,x,y — the renderer's gaze-trace format, so it replays there.
// Readers go by the header's column names and name file and line in every error.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "sim/synthetic_eye.hpp"

namespace gt::eyetrack {

[[nodiscard]] std::string truthHeader();
[[nodiscard]] std::string truthRow(const EyeTruth& t);

// A CSV table of numbers and words, columns by name.
class CsvTable {
public:
    // Throws FormatError naming the file and line; `required` columns must be present.
    [[nodiscard]] static CsvTable load(const std::filesystem::path& file,
                                       const std::vector<std::string>& required);
    // A truth table (eyesim's, or hand labels): every cell but `phase` and `note` empty or a
    // finite number, and frame (and t_ms, when present) strictly increasing whole numbers —
    // a NaN or a row out of order would be scored silently against the wrong frame.
    [[nodiscard]] static CsvTable loadTruth(const std::filesystem::path& file,
                                            const std::vector<std::string>& required);
    // Throws FormatError naming file and line: a cell that is not empty or a finite number, in
    // any column but `textColumns`.
    void requireNumbers(const std::vector<std::string>& textColumns) const;
    // Throws FormatError naming file and line unless `column` has a value on every row, each
    // greater than the one before.
    void requireIncreasing(const std::string& column) const;

    [[nodiscard]] std::size_t rows() const { return mRows.size(); }
    [[nodiscard]] bool has(const std::string& column) const { return mIndex.count(column) > 0; }
    [[nodiscard]] const std::string& text(std::size_t row, const std::string& column) const;
    // Throws FormatError if the cell is not a number (empty cells: NaN).
    [[nodiscard]] double number(std::size_t row, const std::string& column) const;

private:
    [[nodiscard]] std::string where(std::size_t row) const; // "FILE:LINE"

    std::string mFile;
    std::map<std::string, std::size_t> mIndex;
    std::vector<std::vector<std::string>> mRows;
    std::vector<int> mLines;
};

} // namespace gt::eyetrack
