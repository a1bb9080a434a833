#!/usr/bin/env python3
"""Refit the pupil detector's reported confidence (eyetrack/pupil/answer_confidence.cpp).

The confidence is a logistic regression of "this answer is right" (within eyescore's radius of
the true centre, the pupil at least half visible) on what the detector measured on the answer,
in two parts:
  - the frame's own evidence (frameLogit), fitted on answers given without history (`eyescore
    --cold`: the detector forgets everything before each frame, as on a recording's first
    frame);
  - the ranked answer with its history (rankedLogit), fitted on the answers of ordinary runs;
    where an answer has history, what that adds to the frame's logit is the difference.
Write the answers of development seeds with `gazetrace eyescore --answers FILE.csv` (with and
without --cold), then

    scripts/fit_answer_confidence.py --cold c1.csv [...] --warm w1.csv [...] \\
        [--test-cold tc.csv ...] [--test-warm tw.csv ...]

prints the constants for answer_confidence.cpp and the ROC areas and gate rates of the fitted
probability, on the training answers and on others. The frame part's bias is then set on held-out
answers as answer_confidence.cpp says, not taken from the fit. Newton's method with a small ridge;
only the Python standard library.
"""
import argparse
import csv
import math

FRAME_NAMES = ["bias", "log_product", "visible_support", "support_all", "fill", "axis_ratio",
               "score", "rival_ratio", "inlier_share", "log_contrast"]
RANKED_NAMES = ["bias", "log_product", "visible_support", "fill", "axis_ratio",
                "log_size_factor", "score", "rival_ratio", "last_distance", "no_last",
                "size_known", "level_excess"]


def frame_features(row):
    """The frame's own inputs exactly as frameLogit() forms them."""
    product = float(row["product"])
    score = float(row["score"])
    rival = min(2.0, float(row["rival_score"]) / score) if score > 0 else 0.0
    return [1.0, math.log(max(1e-3, product)), float(row["visible_support"]),
            float(row["support_all"]), float(row["fill"]), float(row["axis_ratio"]), score, rival,
            float(row["inlier_share"]), math.log(max(1.0, float(row["contrast"])))]


def ranked_features(row):
    """The inputs exactly as rankedLogit() forms them."""
    score = float(row["ranked_score"])
    rival = min(2.0, float(row["ranked_rival_score"]) / score) if score > 0 else 0.0
    last = float(row["last_distance"])
    no_last = last < 0
    last_n = 0.0 if no_last else min(3.0, last / max(1.0, float(row["semi_major"])))
    eye = float(row["eye_axis_ratio"])
    return [1.0, math.log(max(1e-3, float(row["ranked_product"]))),
            float(row["visible_support"]), float(row["fill"]),
            eye if eye > 0 else float(row["axis_ratio"]),
            math.log(max(1e-3, float(row["size_factor"]))), score, rival, last_n,
            1.0 if no_last else 0.0, float(row["size_known"]), float(row["level_excess"])]


def has_history(row):
    """As hasHistory() decides it."""
    return (int(row["earlier_frames"]) > 0 or float(row["last_distance"]) >= 0
            or float(row["size_known"]) > 0
            or float(row["eye_axis_ratio"]) > 0 or float(row["level_excess"]) > 0)


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


def fit(xs, ys, ridge=1e-3, iterations=30):
    d = len(xs[0])
    w = [0.0] * d
    for _ in range(iterations):
        h = [[0.0] * d for _ in range(d)]
        g = [0.0] * d
        for x, y in zip(xs, ys):
            p = sigmoid(sum(wi * xi for wi, xi in zip(w, x)))
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


def probabilities(rows, wf, wr):
    out = []
    for row in rows:
        w, x = (wr, ranked_features(row)) if has_history(row) else (wf, frame_features(row))
        out.append(sigmoid(sum(a * b for a, b in zip(w, x))))
    return out


def report(label, rows, wf, wr, gate=0.75):
    if not rows:
        return
    ys = [int(r["right"]) for r in rows]
    probs = probabilities(rows, wf, wr)
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
    wf = fit([frame_features(r) for r in cold], [int(r["right"]) for r in cold])
    warm = load(args.warm)
    wr = fit([ranked_features(r) for r in warm], [int(r["right"]) for r in warm])
    for part, names, w in (("frame", FRAME_NAMES, wf), ("ranked", RANKED_NAMES, wr)):
        for name, value in zip(names, w):
            print(f"{part:7s} {name:16s} {value:.3f}")
    report("train cold", cold, wf, wr)
    report("train warm", warm, wf, wr)
    report("test cold", load(args.test_cold), wf, wr)
    report("test warm", load(args.test_warm), wf, wr)


if __name__ == "__main__":
    main()
