#!/usr/bin/env python3
"""Refit the pupil detector's reported confidence (eyetrack/pupil/answer_confidence.cpp).

The confidence is a logistic regression of "this answer is right" (within eyescore's radius of
the true centre, the pupil at least half visible) on what the detector measured on the answer.
Write the answers of development seeds with `gazetrace eyescore --answers FILE.csv`, then

    scripts/fit_answer_confidence.py train1.csv [train2.csv ...] [--test test.csv ...]

prints the constants for answer_confidence.cpp and the ROC areas of the fitted probability and
of the detector's own product, on the training answers and (with --test) on others. Newton's
method with a small ridge; only the Python standard library.
"""
import argparse
import csv
import math

NAMES = ["bias", "log_product", "visible_support", "fill", "axis_ratio", "log_size_factor",
         "score", "rival_ratio", "last_distance", "no_last", "size_known", "level_excess"]


def features(row):
    """The inputs exactly as answerProbability() forms them."""
    product = float(row["product"])
    score = float(row["score"])
    rival = min(2.0, float(row["rival_score"]) / score) if score > 0 else 0.0
    last = float(row["last_distance"])
    no_last = last < 0
    last_n = 0.0 if no_last else min(3.0, last / max(1.0, float(row["semi_major"])))
    return [1.0, math.log(max(1e-3, product)), float(row["visible_support"]), float(row["fill"]),
            float(row["axis_ratio"]), math.log(max(1e-3, float(row["size_factor"]))), score,
            rival, last_n, 1.0 if no_last else 0.0, float(row["size_known"]),
            float(row.get("level_excess", 0.0))]


def load(paths):
    xs, ys, products = [], [], []
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if float(row["product"]) <= 0:
                    continue
                xs.append(features(row))
                ys.append(int(row["right"]))
                products.append(float(row["product"]))
    return xs, ys, products


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


def fit(xs, ys, ridge=1e-3, iterations=30):
    d = len(xs[0])
    w = [0.0] * d
    for _ in range(iterations):
        h = [[0.0] * d for _ in range(d)]
        g = [0.0] * d
        for x, y in zip(xs, ys):
            z = sum(wi * xi for wi, xi in zip(w, x))
            p = 1.0 / (1.0 + math.exp(-max(-50.0, min(50.0, z))))
            s = p * (1.0 - p)
            for i in range(d):
                g[i] += (y - p) * x[i]
                sx = s * x[i]
                hi = h[i]
                for j in range(i, d):
                    hi[j] += sx * x[j]
        for i in range(d):
            h[i][i] += ridge
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
    return (rank_sum - positives * (positives + 1) / 2) / (positives * negatives)


def report(label, w, xs, ys, products):
    probs = [1.0 / (1.0 + math.exp(-max(-50.0, min(50.0, sum(a * b for a, b in zip(w, x))))))
             for x in xs]
    print(f"{label}: {len(ys)} answers, ROC area {roc_area(probs, ys):.4f} "
          f"(the product alone {roc_area(products, ys):.4f})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("train", nargs="+", help="eyescore --answers CSVs to fit on")
    ap.add_argument("--test", nargs="*", default=[], help="eyescore --answers CSVs to test on")
    args = ap.parse_args()
    xs, ys, products = load(args.train)
    w = fit(xs, ys)
    for name, value in zip(NAMES, w):
        print(f"{name:16s} {value:.3f}")
    report("train", w, xs, ys, products)
    if args.test:
        report("test", w, *load(args.test))


if __name__ == "__main__":
    main()
