"""The group summary of `burrlab analyze thresholds` recomputed with pandas.

Reads every subject's _beh.tsv as an analyst would, checks that the per-subject
estimates cover each subject's scored trials, and recomputes the group's mean,
SD, SEM, Student t interval and geometric mean from the per-subject thresholds;
compares them with the JSON (to 1e-12 relative) and the printed group line, and
checks the group figure was written.
    group_thresholds.py STUDY_DIR THRESHOLDS_JSON THRESHOLDS_TXT
"""
import glob
import json
import math
import os
import sys

import numpy as np
import pandas as pd

# qt(0.975, 11) in R: the Student t quantile for a two-sided 95 % interval of a
# mean of 12 values.
T_975_11 = 2.200985160082949

study, json_path, text_path = sys.argv[1:4]
with open(json_path) as f:
    doc = json.load(f)
with open(text_path) as f:
    text = f.read()
failures = []


def check(what, got, want, rel=1e-12):
    if not math.isclose(got, want, rel_tol=rel, abs_tol=1e-15):
        failures.append(f"{what}: burrlab {got!r}, pandas {want!r}")


# The scored trials per subject, from the exports.
trials = []
for path in sorted(glob.glob(os.path.join(study, "sub-*", "beh", "*_beh.tsv"))):
    frame = pd.read_csv(path, sep="\t", na_values="n/a", keep_default_na=False)
    frame["subject"] = os.path.basename(path).split("_")[0][len("sub-"):]
    trials.append(frame)
trials = pd.concat(trials, ignore_index=True)
scored = trials[trials["practice"] == 0]
counts = scored.groupby("subject").size()
assert len(counts) == 12, f"expected 12 subjects, found {len(counts)}"

per_subject = pd.DataFrame(doc["thresholds"])
assert len(per_subject) == 12, per_subject
for row in per_subject.itertuples():
    if row.n != counts[row.subject]:
        failures.append(f"sub-{row.subject}: n {row.n}, trials {counts[row.subject]}")

values = per_subject.set_index("subject")["value"].astype(float)
n = len(values)
mean = values.mean()
sd = values.std(ddof=1)
sem = sd / math.sqrt(n)
logs = np.log(values)
log_mean = logs.mean()
log_sd = logs.std(ddof=1)
log_sem = log_sd / math.sqrt(n)

assert len(doc["group"]) == 1, doc["group"]
group = doc["group"][0]
if group["n"] != n or group["subjects"] != list(values.index):
    failures.append(f"subjects {group['subjects']} vs {list(values.index)}")
check("mean", group["mean"], mean)
check("sd", group["sd"], sd)
check("sem", group["sem"], sem)
check("ci low", group["ci"][0], mean - T_975_11 * sem)
check("ci high", group["ci"][1], mean + T_975_11 * sem)
geo = group["geometric"]
check("geometric mean", geo["mean"], math.exp(log_mean))
check("geometric SD factor", geo["sd_factor"], math.exp(log_sd))
check("geometric SEM factor", geo["sem_factor"], math.exp(log_sem))
check("geometric ci low", geo["ci"][0], math.exp(log_mean - T_975_11 * log_sem))
check("geometric ci high", geo["ci"][1], math.exp(log_mean + T_975_11 * log_sem))

line = (
    f"group constant: mean {mean:.4g} ratio ± {sem:.3g} SEM "
    f"[{mean - T_975_11 * sem:.4g}, {mean + T_975_11 * sem:.4g}] 95 % CI, "
    f"SD {sd:.3g}; geometric mean {math.exp(log_mean):.4g} ratio ×/÷ "
    f"{math.exp(log_sem):.4g} [{math.exp(log_mean - T_975_11 * log_sem):.4g}, "
    f"{math.exp(log_mean + T_975_11 * log_sem):.4g}] 95 % CI, SD factor "
    f"{math.exp(log_sd):.4g}; n = 12 subjects"
)
if line not in text.splitlines():
    failures.append(f"printed group line missing; expected\n  {line}\nin\n{text}")

# The group figure the text names.
figure = os.path.join(os.path.dirname(text_path), "figures",
                      "thresholds_constant.png")
if f"  figure {figure}" not in text.splitlines():
    failures.append(f"no line '  figure {figure}' in\n{text}")
elif not open(figure, "rb").read(8) == b"\x89PNG\r\n\x1a\n":
    failures.append(f"{figure} is not a PNG")

if failures:
    print("\n".join(failures))
    sys.exit(1)
print(f"group of {n}: mean {mean:.6g} ± {sem:.3g} SEM, geometric mean "
      f"{math.exp(log_mean):.6g}: burrlab agrees with pandas")
