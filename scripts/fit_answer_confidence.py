#!/usr/bin/env python3
"""Refit the pupil detector's reported confidence (eyetrack/pupil/answer_confidence.cpp).

The confidence is a logistic regression of "this answer is right" (within eyescore's radius of
the true centre, the pupil at least half visible) on what the detector measured on the answer,
in two parts that add up in the logit:
  - the frame's own evidence, fitted on answers given without history (`eyescore --cold`: the
    detector forgets everything before each frame, as on a recording's first frame);
  - what the history adds (the last answer, the learnt pupil size, level and shape), fitted on
    the answers of ordinary runs with the frame's part held fixed. It is nil without history,
    so a first frame is judged on its own evidence and the history can only add doubt or
    assurance.
Write the answers of development seeds with `gazetrace eyescore --answers FILE.csv` (with and
without --cold), then

    scripts/fit_answer_confidence.py --cold c1.csv [...] --warm w1.csv [...] \\
        [--test-cold tc.csv ...] [--test-warm tw.csv ...]

prints the constants for answer_confidence.cpp and the ROC areas of the fitted probability and
of the detector's own product, on the training answers and on others. Newton's method with a
small ridge; only the Python standard library.
"""
import argparse
import csv
import math

FRAME_NAMES = ["bias", "log_product", "visible_support", "fill", "axis_ratio", "score",
               "rival_ratio", "inlier_share", "log_contrast"]
HISTORY_NAMES = ["has_last", "last_distance", "size_known", "log_size_factor", "level_excess",
                 "eye_axis_gain"]


def frame_features(row):
    """The frame's own inputs exactly as answerProbability() forms them."""
    product = float(row["product"])
    score = float(row["score"])
    rival = min(2.0, float(row["rival_score"]) / score) if score > 0 else 0.0
    return [1.0, math.log(max(1e-3, product)), float(row["visible_support"]), float(row["fill"]),
            float(row["axis_ratio"]), score, rival, float(row["inlier_share"]),
            math.log(max(1.0, float(row["contrast"])))]


def history_features(row):
    """What the history adds, as answerProbability() forms it: all nil without history."""
    last = float(row["last_distance"])
    has_last = last >= 0
    last_n = min(3.0, last / max(1.0, float(row["semi_major"]))) if has_last else 0.0
    size_known = float(row["size_known"]) > 0
    eye = float(row["eye_axis_ratio"])
    eye_gain = eye - float(row["axis_ratio"]) if eye > 0 else 0.0
    return [1.0 if has_last else 0.0, last_n, 1.0 if size_known else 0.0,
            math.log(max(1e-3, float(row["size_factor"]))) if size_known else 0.0,
            float(row["level_excess"]), eye_gain]


def load(paths):
    rows = []
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if float(row["product"]) > 0:
                    rows.append(row)
    return rows


def solve(a, b):
    """Gaussian elimination with partial pivoting (a is small and well conditioned)."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(c + 1, n):
            k = m[r][c] / m[c][c]
            for j in range(c, n + 1):
                m[r][j] -= k * m[c][j]
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        x[r] = (m[r][n] - sum(m[r][j] * x[j] for j in range(r + 1, n))) / m[r][r]
    return x


def sigmoid(z):
    return 1.0 / (1.0 + math.exp(-max(-50.0, min(50.0, z))))


def fit(xs, ys, offsets, ridge=1e-3, iterations=30):
    """Logistic regression with a fixed offset added to each answer's logit."""
    d = len(xs[0])
    w = [0.0] * d
    for _ in range(iterations):
        h = [[0.0] * d for _ in range(d)]
        g = [0.0] * d
        for x, y, o in zip(xs, ys, offsets):
            p = sigmoid(o + sum(wi * xi for wi, xi in zip(w, x)))
            s = p * (1.0 - p)
            for i in range(d):
                g[i] += (y - p) * x[i]
                sx = s * x[i]
                hi = h[i]
                for j in range(i, d):
                    hi[j] += sx * x[j]
        for i in range(d):
            h[i][i] += ridge
            g[i] -= ridge * w[i]
            for j in range(i):
                h[i][j] = h[j][i]
        step = solve(h, g)
        w = [wi + si for wi, si in zip(w, step)]
        if max(abs(si) for si in step) < 1e-9:
            break
    return w


def roc_area(scores, ys):
    """Mann-Whitney U over (score, right) pairs, ties counted half."""
    pairs = sorted(zip(scores, ys))
    rank_sum, positives, i = 0.0, 0, 0
    while i < len(pairs):
        j = i
        while j < len(pairs) and pairs[j][0] == pairs[i][0]:
            j += 1
        rank = 0.5 * (i + j - 1) + 1
        for k in range(i, j):
            if pairs[k][1]:
                rank_sum += rank
                positives += 1
        i = j
    negatives = len(pairs) - positives
    if positives == 0 or negatives == 0:
        return 0.0
    return (rank_sum - positives * (positives + 1) / 2) / (positives * negatives)


def probabilities(rows, wf, wh):
    out = []
    for row in rows:
        z = sum(a * b for a, b in zip(wf, frame_features(row)))
        z += sum(a * b for a, b in zip(wh, history_features(row)))
        out.append(sigmoid(z))
    return out


def report(label, rows, wf, wh, gate=0.75):
    if not rows:
        return
    ys = [int(r["right"]) for r in rows]
    probs = probabilities(rows, wf, wh)
    products = [float(r["product"]) for r in rows]
    right = [p for p, y in zip(probs, ys) if y]
    wrong = [p for p, y in zip(probs, ys) if not y]
    kept = sum(p >= gate for p in right) / max(1, len(right))
    rejected = sum(p < gate for p in wrong) / max(1, len(wrong))
    print(f"{label}: {len(ys)} answers, ROC area {roc_area(probs, ys):.4f} (the product alone "
          f"{roc_area(products, ys):.4f}); at {gate}: right kept {kept:.3f}, "
          f"wrong rejected {rejected:.3f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cold", nargs="+", required=True, help="eyescore --cold --answers CSVs")
    ap.add_argument("--warm", nargs="+", required=True, help="eyescore --answers CSVs")
    ap.add_argument("--test-cold", nargs="*", default=[], help="cold CSVs to test on")
    ap.add_argument("--test-warm", nargs="*", default=[], help="warm CSVs to test on")
    args = ap.parse_args()
    cold = load(args.cold)
    wf = fit([frame_features(r) for r in cold], [int(r["right"]) for r in cold], [0.0] * len(cold))
    warm = load(args.warm)
    offsets = [sum(a * b for a, b in zip(wf, frame_features(r))) for r in warm]
    wh = fit([history_features(r) for r in warm], [int(r["right"]) for r in warm], offsets)
    for name, value in zip(FRAME_NAMES + HISTORY_NAMES, wf + wh):
        print(f"{name:16s} {value:.3f}")
    report("train cold", cold, wf, wh)
    report("train warm", warm, wf, wh)
    report("test cold", load(args.test_cold), wf, wh)
    report("test warm", load(args.test_warm), wf, wh)


if __name__ == "__main__":
    main()
