#!/usr/bin/env python3
"""The report a person opens: DIR/report.html from what `hil fly --out DIR` or `hil campaign --out DIR`
wrote (DIR/throws.csv, and DIR/attempt_<n>.csv when present). docs/report.md says what each figure shows.

usage: make_report.py DIR

One self-contained page: the figures are PNG images made with matplotlib (Agg), inlined as base64
and also written beside it as DIR/fig_<name>.png; the animation of each attempt is the recorded
time series (at 50 Hz) as JSON in the page, drawn on <canvas> by a small player. No server, no
external script. Only the standard library and matplotlib.

Exit codes: 0 written, 1 unreadable input, 2 bad arguments, 3 matplotlib missing (hil names the
Debian package then).
"""

import base64
import csv
import html
import io
import json
import math
import os
import re
import sys

NO_MATPLOTLIB = 3
# The columns of throws.csv before a campaign's drawn parameters.
RESULT_COLUMNS = {"throw", "outcome", "flight_s", "catch_height_m", "catch_x_m", "catch_y_m", "travel_m",
                  "energy_error_J", "abort_reason", "vehicle_crashed", "seed", "planned_height_m",
                  "optimal_height_m", "thrower", "innovation_switches"}
NOT_A_CATCH = {"throw_only", "offset_practice"}  # attempts that did not try to catch
ANIMATION_PERIOD_S = 0.02  # 50 Hz
OUTCOME_COLOURS = {"caught": "tab:green", "dropped": "tab:orange", "missed": "tab:red", "aborted": "tab:purple",
                   "offset_practice": "tab:blue", "throw_only": "tab:gray"}


def wilson95(k, n):
    """Wilson's score interval for k successes in n trials at 95% (as `hil campaign` prints it)."""
    if n == 0:
        return 0.0, 1.0
    z = 1.959964
    p = k / n
    d = 1.0 + z * z / n
    centre = (p + z * z / (2.0 * n)) / d
    half = z * math.sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n)) / d
    return max(0.0, centre - half), min(1.0, centre + half)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(row, key, default=float("nan")):
    try:
        return float(row.get(key, ""))
    except (TypeError, ValueError):
        return default


def cause_of(row):
    """An attempt's failure cause as `hil campaign` counts it (None when caught or not a catch)."""
    outcome = row["outcome"]
    if outcome == "caught" or outcome in NOT_A_CATCH:
        return None
    reason = row.get("abort_reason", "")
    return f"{outcome} ({reason})" if reason else outcome


def attempt_files(out_dir):
    found = {}
    for name in os.listdir(out_dir):
        m = re.fullmatch(r"attempt_(\d+)\.csv", name)
        if m:
            found[int(m.group(1))] = os.path.join(out_dir, name)
    return dict(sorted(found.items()))


class Figures:
    """Saves each figure as DIR/fig_<name>.png and keeps its bytes for the page."""

    def __init__(self, plt, out_dir):
        self.plt = plt
        self.out_dir = out_dir
        self.items = []  # (name, title, caption, png bytes)

    def add(self, fig, name, title, caption):
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=90)
        self.plt.close(fig)
        data = buf.getvalue()
        with open(os.path.join(self.out_dir, f"fig_{name}.png"), "wb") as f:
            f.write(data)
        self.items.append((name, title, caption, data))


def tilt_deg(nx, nz):
    return math.degrees(math.atan2(nx, nz))


def window(rows, key, tasks, before_s, after_s):
    """The rows from before_s before the first row whose `key` is in `tasks` to after_s after the last."""
    idx = [i for i, r in enumerate(rows) if r.get(key) in tasks]
    if not idx:
        return [], 0.0
    t0 = number(rows[idx[0]], "t_s")
    t1 = number(rows[idx[-1]], "t_s")
    return [r for r in rows if t0 - before_s <= number(r, "t_s") <= t1 + after_s], t0


def has_inputs(rows):
    return bool(rows) and "v1_thrust_mps2" in rows[0]


def figure_throw(plt, figs, attempts, throws):
    """Fig. 5: the thrower's trajectory and inputs during the throw."""
    for n, rows in attempts.items():
        sel, t0 = window(rows, "task1", {"throwing"}, 0.2, 0.6)
        if sel:
            break
    else:
        return
    t = [number(r, "t_s") - t0 for r in sel]
    fig, ax = plt.subplots(2, 2, figsize=(10, 6.5))
    key = "plate1" if "plate1_x" in sel[0] else "v1"
    ax[0][0].plot([number(r, f"{key}_x") for r in sel], [number(r, f"{key}_z") for r in sel], label="plate 1")
    ax[0][0].plot([number(r, "pole_x") for r in sel], [number(r, "pole_z") for r in sel], label="pole centre")
    ax[0][0].set_xlabel("x [m]")
    ax[0][0].set_ylabel("z [m]")
    ax[0][0].set_title("trajectory (side view)")
    ax[0][0].axis("equal")
    ax[0][0].legend(fontsize=8)
    ax[0][1].plot(t, [number(r, "v1_x") for r in sel], label="thrower x")
    ax[0][1].plot(t, [number(r, "v1_z") for r in sel], label="thrower z")
    ax[0][1].plot(t, [number(r, "pole_z") for r in sel], label="pole centre z")
    if "plate1_nx" in sel[0]:
        ax2 = ax[0][1].twinx()
        ax2.plot(t, [tilt_deg(number(r, "plate1_nx"), number(r, "plate1_nz")) for r in sel], "k--", lw=0.8,
                 label="thrower pitch")
        ax2.set_ylabel("pitch (x-z tilt) [deg]")
        ax2.legend(fontsize=8, loc="lower right")
    ax[0][1].set_xlabel("t since the throw began [s]")
    ax[0][1].set_ylabel("[m]")
    ax[0][1].legend(fontsize=8, loc="upper left")
    ax[0][1].set_title("positions")
    if has_inputs(sel):
        ax[1][0].plot(t, [number(r, "v1_thrust_mps2") for r in sel])
        ax[1][1].plot(t, [number(r, "v1_p_radps") for r in sel], label="p")
        ax[1][1].plot(t, [number(r, "v1_q_radps") for r in sel], label="q")
        ax[1][1].plot(t, [number(r, "v1_r_radps") for r in sel], label="r")
        ax[1][1].legend(fontsize=8)
    ax[1][0].set_title("commanded collective thrust")
    ax[1][0].set_ylabel("a_q [m/s²]")
    ax[1][1].set_title("commanded body rates")
    ax[1][1].set_ylabel("[rad/s]")
    for a in (ax[1][0], ax[1][1]):
        a.set_xlabel("t since the throw began [s]")
    end = [number(r, "t_s") - t0 for r in sel if r["task1"] == "throwing"][-1]
    for a in (ax[0][1], ax[1][0], ax[1][1]):
        a.axvline(0.0, color="gray", lw=0.5)
        a.axvline(end, color="gray", lw=0.5, ls=":")
    fig.suptitle(f"Fig. 5 — the throw (attempt {n}): thrower's trajectory and inputs")
    fig.tight_layout()
    figs.add(fig, "throw", "Fig. 5 — the throw",
             f"Attempt {n}: the thrower (vehicle 1) from 0.2 s before its task 'throwing' began to 0.6 s after it "
             "ended (dotted line). Top: the plate's and the pole's paths in the x-z plane, positions against time "
             "and the thrower's pitch. Bottom: the inputs the ground station commanded (collective thrust and "
             "body rates, RATE_THRUST as the firmware accepted it).")


def pick_catch_attempt(attempts, throws):
    outcome = {int(r["throw"]): r["outcome"] for r in throws if r.get("throw", "").isdigit()}
    order = sorted(attempts, key=lambda n: (outcome.get(n) != "caught", outcome.get(n) == "offset_practice", n))
    for n in order:
        sel, t0 = window(attempts[n], "task2", {"catching"}, 0.3, 1.0)
        if sel:
            return n, sel, t0
    return None, [], 0.0


def figure_catch(plt, figs, attempts, throws):
    """Fig. 7: the catcher's inputs during a catch manoeuvre."""
    n, sel, t0 = pick_catch_attempt(attempts, throws)
    if not sel:
        return
    t = [number(r, "t_s") - t0 for r in sel]
    fig, ax = plt.subplots(3, 1, figsize=(9, 7.5), sharex=True)
    for c in "xyz":
        ax[0].plot(t, [number(r, f"v2_{c}") for r in sel], label=f"catcher {c}")
    ax[0].plot(t, [number(r, "pole_z") for r in sel], "k:", label="pole centre z")
    ax[0].set_ylabel("[m]")
    ax[0].legend(fontsize=8, ncol=4)
    ax[0].set_title("catcher position")
    if has_inputs(sel):
        ax[1].plot(t, [number(r, "v2_thrust_mps2") for r in sel])
        for c, name in (("p", "p"), ("q", "q"), ("r", "r")):
            ax[2].plot(t, [number(r, f"v2_{c}_radps") for r in sel], label=name)
        ax[2].legend(fontsize=8)
    ax[1].set_ylabel("a_q [m/s²]")
    ax[1].set_title("commanded collective thrust")
    ax[2].set_ylabel("[rad/s]")
    ax[2].set_title("commanded body rates")
    ax[2].set_xlabel("t since the catch manoeuvre began [s]")
    end = [number(r, "t_s") - t0 for r in sel if r["task2"] == "catching"][-1]
    for a in ax:
        a.axvline(0.0, color="gray", lw=0.5)
        a.axvline(end, color="gray", lw=0.5, ls=":")
    outcome = next((r["outcome"] for r in throws if r.get("throw") == str(n)), "?")
    fig.suptitle(f"Fig. 7 — a catch manoeuvre's inputs (attempt {n}, {outcome})")
    fig.tight_layout()
    figs.add(fig, "catch", "Fig. 7 — a catch manoeuvre",
             f"Attempt {n} ({outcome}): the catcher (vehicle 2) from 0.3 s before its task 'catching' began to "
             "1 s after it ended (dotted line): its position and the commanded collective thrust and body rates.")


def crossing(rows, height_m):
    """Where the pole's lower end last came down through height_m (x, y), from an attempt's time series."""
    if not rows or "end0_z" not in rows[0]:
        return None
    found = None
    prev = None
    for r in rows:
        ends = [(number(r, f"end{i}_x"), number(r, f"end{i}_y"), number(r, f"end{i}_z")) for i in (0, 1)]
        low = min(ends, key=lambda e: e[2])
        if prev is not None and prev[2] > height_m >= low[2]:
            f = (prev[2] - height_m) / (prev[2] - low[2])
            found = (prev[0] + f * (low[0] - prev[0]), prev[1] + f * (low[1] - prev[1]))
        prev = low
    return found


def figure_heights(plt, figs, throws, attempts):
    """Fig. 9: the optimal catching heights and the catch points."""
    rows = [r for r in throws if number(r, "catch_height_m", -1.0) > 0.0 or number(r, "planned_height_m", -1.0) > 0]
    if not rows:
        return
    many = len(throws) > 40
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    n = [int(r["throw"]) for r in rows]
    h = [number(r, "catch_height_m", -1.0) for r in rows]
    planned = [number(r, "planned_height_m", -1.0) for r in rows]
    ax[0].plot([a for a, b in zip(n, h) if b > 0], [b for b in h if b > 0], "o" if many else "o-", ms=3 if many else 6,
               label="lower end at the impact (truth)")
    if any(p > 0 for p in planned):
        ax[0].plot([a for a, b in zip(n, planned) if b > 0], [b for b in planned if b > 0], "s--", ms=5,
                   label="the ground station's catching height")
    ax[0].set_xlabel("throw")
    ax[0].set_ylabel("height [m]")
    ax[0].set_title("catching heights")
    ax[0].legend(fontsize=8)
    for outcome in sorted({r["outcome"] for r in rows}):
        pts = [r for r in rows if r["outcome"] == outcome and number(r, "catch_height_m", -1.0) > 0]
        if not pts:
            continue
        ax[1].scatter([number(r, "catch_x_m") for r in pts], [number(r, "catch_y_m") for r in pts],
                      s=10 if many else 30, color=OUTCOME_COLOURS.get(outcome, "k"), label=outcome)
        if not many:
            for r in pts:
                ax[1].annotate(r["throw"], (number(r, "catch_x_m"), number(r, "catch_y_m")), fontsize=8,
                               xytext=(3, 3), textcoords="offset points")
    crossed = []
    for r in rows:
        n_ = int(r["throw"])
        if number(r, "catch_height_m", -1.0) <= 0 and number(r, "planned_height_m", -1.0) > 0 and n_ in attempts:
            xy = crossing(attempts[n_], number(r, "planned_height_m"))
            if xy:
                crossed.append((n_, xy))
    if crossed:
        ax[1].scatter([xy[0] for _, xy in crossed], [xy[1] for _, xy in crossed], s=30, facecolors="none",
                      edgecolors="tab:blue", label="no impact: lower end through the catching height")
        for n_, xy in crossed:
            ax[1].annotate(str(n_), xy, fontsize=8, xytext=(3, 3), textcoords="offset points")
    if not many:
        ax[0].set_xticks(sorted({int(r["throw"]) for r in throws}))
    ax[1].set_xlabel("x [m]")
    ax[1].set_ylabel("y [m]")
    ax[1].set_title("catch points (top view)")
    ax[1].axis("equal")
    ax[1].legend(fontsize=8)
    fig.suptitle("Fig. 9 — catching heights and catch points")
    fig.tight_layout()
    figs.add(fig, "heights", "Fig. 9 — catching heights and catch points",
             "Left: per throw, the height of the pole's lower end where it struck the catcher's plate (truth) and, "
             "where recorded, the catching height the ground station aimed for (its adapted optimum). Right: where "
             "the impacts were, seen from above, by outcome (numbers: the throw); for a throw without an impact "
             "(throw-only, practice 1 m off) where its lower end came down through that catching height.")


def figure_travel_energy(plt, figs, throws):
    """Fig. 10: the catcher's travel and the pole's energy right after the impact, per throw."""
    if not throws:
        return
    many = len(throws) > 40
    n = [int(r["throw"]) for r in throws]
    travel = [number(r, "travel_m", 0.0) for r in throws]
    energy = [abs(number(r, "energy_error_J", 0.0)) if number(r, "catch_height_m", -1.0) > 0 else float("nan")
              for r in throws]
    colours = [OUTCOME_COLOURS.get(r["outcome"], "k") for r in throws]
    fig, ax = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    if many:
        ax[0].scatter(n, travel, s=6, c=colours)
        ax[1].scatter(n, energy, s=6, c=colours)
    else:
        ax[0].bar(n, travel, color=colours)
        ax[1].bar(n, [0.0 if math.isnan(e) else e for e in energy], color=colours)
    ax[0].set_ylabel("travel [m]")
    ax[0].set_title("catcher's travel: waiting point to catch point")
    ax[1].set_ylabel("|E − E*| [J]")
    ax[1].set_title("pole energy right after the impact (paper: 0.0102 J on average)")
    ax[1].set_xlabel("throw")
    if not many:
        ax[1].set_xticks(n)
    handles = [plt.Line2D([], [], marker="s", ls="", color=c, label=o) for o, c in OUTCOME_COLOURS.items()
               if any(r["outcome"] == o for r in throws)]
    ax[0].legend(handles=handles, fontsize=8, ncol=3)
    fig.suptitle("Fig. 10 — travel distance and energy after the impact, per throw")
    fig.tight_layout()
    figs.add(fig, "travel_energy", "Fig. 10 — travel and energy",
             "Per throw, coloured by outcome: the horizontal distance from the catcher's waiting point to where the "
             "pole came to it (what adapting the waiting point reduces), and the pole's energy right after the "
             "impact minus the energy E* of balancing upright (none without an impact).")


def success(throws):
    tries = [r for r in throws if r["outcome"] not in NOT_A_CATCH]
    caught = sum(1 for r in tries if r["outcome"] == "caught")
    return caught, len(tries)


def figure_rate(plt, figs, throws):
    """The success rate with its 95% interval, as the attempts add up."""
    tries = [r for r in throws if r["outcome"] not in NOT_A_CATCH]
    if not tries:
        return
    xs, rate, lo, hi = [], [], [], []
    k = 0
    for i, r in enumerate(tries, 1):
        k += r["outcome"] == "caught"
        a, b = wilson95(k, i)
        xs.append(i)
        rate.append(100.0 * k / i)
        lo.append(100.0 * a)
        hi.append(100.0 * b)
    fig, ax = plt.subplots(figsize=(9, 3.8))
    ax.fill_between(xs, lo, hi, alpha=0.3, label="95% interval (Wilson)")
    ax.plot(xs, rate, "o-" if len(xs) <= 40 else "-", ms=4, label="caught so far")
    ax.set_ylim(0, 105)
    ax.set_xlabel("attempts to catch")
    ax.set_ylabel("caught [%]")
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title(f"success rate: {k} of {len(tries)} = {rate[-1]:.1f}% (95% interval {lo[-1]:.1f}–{hi[-1]:.1f}%)")
    fig.tight_layout()
    figs.add(fig, "rate", "Success rate",
             "The share of attempts to catch (practice and throw-only attempts left out) caught and balanced again "
             "for 3 s, as the attempts add up, with its 95% confidence interval (Wilson's score interval, as "
             "`hil campaign` prints it).")


def parameter_keys(throws):
    if not throws:
        return []
    return [k for k in throws[0].keys() if k not in RESULT_COLUMNS]


def figure_failures(plt, figs, throws):
    """Failures by cause, and against each drawn parameter (a campaign's throws.csv)."""
    tries = [r for r in throws if r["outcome"] not in NOT_A_CATCH]
    causes = {}
    for r in tries:
        c = cause_of(r)
        if c:
            causes[c] = causes.get(c, 0) + 1
    keys = parameter_keys(throws)
    if keys:
        cats = ["caught"] + sorted(causes)
        cols = 4
        rows_n = math.ceil(len(keys) / cols)
        fig, axs = plt.subplots(rows_n, cols, figsize=(13, 1.0 + rows_n * (0.9 + 0.3 * len(cats))), squeeze=False)
        for i, key in enumerate(keys):
            ax = axs[i // cols][i % cols]
            for j, cat in enumerate(cats):
                sel = [r for r in tries if (cause_of(r) or "caught") == cat]
                xs = [number(r, key) for r in sel]
                ys = [j + 0.3 * (((int(r["throw"]) * 2654435761) % 1000) / 1000.0 - 0.5) for r in sel]
                ax.scatter(xs, ys, s=5 if cat == "caught" else 14, alpha=0.4 if cat == "caught" else 0.9,
                           color="tab:green" if cat == "caught" else "tab:red")
            ax.set_yticks(range(len(cats)))
            ax.set_yticklabels(cats if i % cols == 0 else [""] * len(cats), fontsize=7)
            ax.set_title(key, fontsize=8)
            ax.tick_params(axis="x", labelsize=7)
        for i in range(len(keys), rows_n * cols):
            axs[i // cols][i % cols].axis("off")
        fig.suptitle("Outcome against each drawn parameter (each dot an attempt)")
        fig.tight_layout()
        figs.add(fig, "failures_vs_parameters", "Failures against the drawn parameters",
                 "One panel per randomised plant parameter: each attempt's drawn value (x) on the row of its outcome "
                 "(caught, or the failure cause). Failures bunched at one end of a range show the condition that "
                 "makes the catch fail; the table below gives the failure rate by fifth of each range.")
    if tries:
        fig, ax = plt.subplots(figsize=(9, 1.2 + 0.45 * max(1, len(causes))))
        names = sorted(causes, key=lambda c: causes[c])
        if names:
            ax.barh(names, [causes[c] for c in names], color="tab:red")
        else:
            ax.text(0.5, 0.5, "no failures", ha="center", va="center", transform=ax.transAxes)
            ax.set_yticks([])
        ax.set_xlabel("attempts")
        ax.set_title(f"failures by cause ({sum(causes.values())} of {len(tries)} attempts to catch)")
        fig.tight_layout()
        figs.add(fig, "failures", "Failures by cause",
                 "How many attempts to catch failed, by cause: the referee's outcome (dropped, missed, aborted) "
                 "and, for an aborted one, the ground station's reason.")
    return causes


def failure_table(throws):
    """HTML: the failure rate by fifth (quintile) of each drawn parameter's values."""
    keys = parameter_keys(throws)
    tries = [r for r in throws if r["outcome"] not in NOT_A_CATCH]
    if not keys or len(tries) < 10:
        return ""
    out = ["<table><tr><th>parameter</th>" + "".join(f"<th>fifth {i + 1}</th>" for i in range(5)) +
           "<th>spread</th></tr>"]
    lines = []
    for key in keys:
        vals = sorted((number(r, key), r["outcome"] != "caught") for r in tries)
        cells = []
        rates = []
        for q in range(5):
            part = vals[q * len(vals) // 5:(q + 1) * len(vals) // 5]
            if not part:
                cells.append("<td>–</td>")
                continue
            failed = sum(1 for _, f in part if f)
            rate = 100.0 * failed / len(part)
            rates.append(rate)
            cells.append(f"<td title='{part[0][0]:.4g} to {part[-1][0]:.4g}'>{rate:.1f}% "
                         f"<small>({part[0][0]:.3g}–{part[-1][0]:.3g})</small></td>")
        spread = max(rates) - min(rates) if rates else 0.0
        lines.append((spread, f"<tr><td>{html.escape(key)}</td>{''.join(cells)}<td>{spread:.1f}</td></tr>"))
    out += [line for _, line in sorted(lines, key=lambda x: -x[0])]
    out.append("</table>")
    return ("<h2>Failure rate by fifth of each drawn parameter</h2><p>Attempts sorted by the parameter's drawn value "
            "and cut into five equal groups; each cell is the share of that group that was not caught (the group's "
            "range beneath). Sorted by spread: the parameters at the top are the conditions that decide.</p>" +
            "".join(out))


def animation_data(attempts, throws):
    """The recorded time series at 50 Hz, per attempt, for the player."""
    outcome = {r.get("throw"): r["outcome"] for r in throws}
    data = []
    for n, rows in attempts.items():
        if not rows or "plate1_x" not in rows[0]:
            continue
        frames, tasks = [], []
        next_t = -1e9
        last_tasks = None
        for r in rows:
            t = number(r, "t_s")
            now_tasks = (r["task1"], r["task2"])
            if now_tasks != last_tasks:
                tasks.append([round(t, 3), r["task1"], r["task2"]])
                last_tasks = now_tasks
            if t + 1e-9 < next_t:
                continue
            next_t = t + ANIMATION_PERIOD_S
            f = [t]
            for key in ("v1_x", "v1_y", "v1_z", "plate1_x", "plate1_y", "plate1_z", "plate1_nx", "plate1_ny",
                        "plate1_nz", "v2_x", "v2_y", "v2_z", "plate2_x", "plate2_y", "plate2_z", "plate2_nx",
                        "plate2_ny", "plate2_nz", "end0_x", "end0_y", "end0_z", "end1_x", "end1_y", "end1_z"):
                f.append(number(r, key))
            frames.append([round(v, 3) for v in f])
        data.append({"attempt": n, "outcome": outcome.get(str(n), "?"), "tasks": tasks,
                     "fields": ["t", "vehicle1", "plate1", "normal1", "vehicle2", "plate2", "normal2", "end0", "end1"],
                     "frames": frames})
    return data


PLAYER_JS = r"""
(function () {
  const data = JSON.parse(document.getElementById('animation-data').textContent);
  if (!data.length) return;
  const sel = document.getElementById('anim-attempt'), slider = document.getElementById('anim-time');
  const play = document.getElementById('anim-play'), speed = document.getElementById('anim-speed');
  const label = document.getElementById('anim-label');
  const side = document.getElementById('anim-side').getContext('2d');
  const top = document.getElementById('anim-top').getContext('2d');
  const ARM = 0.17, PLATE = 0.06;  // m: drawing sizes (plant.yaml's arm and plate radius)
  const TRAIL = 100;  // frames of the pole centre's path drawn: 2 s
  data.forEach((a, i) => { const o = document.createElement('option'); o.value = i;
    o.textContent = 'attempt ' + a.attempt + ' (' + a.outcome + ')'; sel.appendChild(o); });
  let cur = null, k = 0, playing = false, last = null, bounds = null;
  function v(f, i) { return [f[i], f[i + 1], f[i + 2]]; }
  function choose(i) {
    cur = data[i]; k = 0; slider.max = cur.frames.length - 1; slider.value = 0;
    let lo = [1e9, 1e9, 0], hi = [-1e9, -1e9, 0.5];
    for (const f of cur.frames) for (const j of [1, 10, 19, 22]) for (let c = 0; c < 3; ++c) {
      lo[c] = Math.min(lo[c], f[j + c]); hi[c] = Math.max(hi[c], f[j + c]); }
    bounds = {lo: lo.map(x => x - 0.4), hi: hi.map(x => x + 0.4)}; draw();
  }
  function view(ctx, a, b) {  // a, b: the axes drawn (0 x, 1 y, 2 z)
    const w = ctx.canvas.width, h = ctx.canvas.height;
    const s = Math.min((w - 20) / (bounds.hi[a] - bounds.lo[a]), (h - 20) / (bounds.hi[b] - bounds.lo[b]));
    const ox = (w - (bounds.hi[a] - bounds.lo[a]) * s) / 2, oy = (h - (bounds.hi[b] - bounds.lo[b]) * s) / 2;
    return p => [ox + (p[a] - bounds.lo[a]) * s, h - oy - (p[b] - bounds.lo[b]) * s];
  }
  function line(ctx, m, p, q, colour, width) {
    const A = m(p), B = m(q); ctx.strokeStyle = colour; ctx.lineWidth = width;
    ctx.beginPath(); ctx.moveTo(A[0], A[1]); ctx.lineTo(B[0], B[1]); ctx.stroke();
  }
  function across(c, n, a, r) {  // a segment of half-length r through c, perpendicular to n, in the view plane
    let d = [0, 0, 0]; d[a] = n[2]; d[2] = -n[a];
    const l = Math.hypot(d[a], d[2]) || 1;
    return [c.map((x, i) => x - r * d[i] / l), c.map((x, i) => x + r * d[i] / l)];
  }
  function drawView(ctx, a, b, f) {
    const w = ctx.canvas.width, h = ctx.canvas.height, m = view(ctx, a, b);
    ctx.clearRect(0, 0, w, h); ctx.fillStyle = '#fafafa'; ctx.fillRect(0, 0, w, h);
    if (b === 2) line(ctx, m, [bounds.lo[0], bounds.lo[1], 0], [bounds.hi[0], bounds.hi[1], 0], '#888', 1);
    ctx.strokeStyle = '#bbb'; ctx.lineWidth = 1; ctx.beginPath();  // the pole centre's last 2 s
    for (let j = Math.max(0, k - TRAIL); j <= k; ++j) { const g = cur.frames[j];
      const P = m([(g[19] + g[22]) / 2, (g[20] + g[23]) / 2, (g[21] + g[24]) / 2]);
      if (j === Math.max(0, k - TRAIL)) ctx.moveTo(P[0], P[1]); else ctx.lineTo(P[0], P[1]); }
    ctx.stroke();
    [[1, 4, 7, '#1f77b4'], [10, 13, 16, '#d62728']].forEach(([vi, pi, ni], idx) => {
      const colour = idx === 0 ? '#1f77b4' : '#d62728';
      const body = v(f, vi), plate = v(f, pi), n = v(f, ni);
      if (b === 2) {
        const [p, q] = across(body, n, a, ARM); line(ctx, m, p, q, colour, 3);
        line(ctx, m, body, plate, colour, 1);
        const [r, s] = across(plate, n, a, PLATE); line(ctx, m, r, s, '#333', 4);
      } else {
        const C = m(body), P = m(plate), R = Math.abs(m([ARM, 0, 0])[0] - m([0, 0, 0])[0]);
        ctx.strokeStyle = colour; ctx.lineWidth = 2; ctx.beginPath(); ctx.arc(C[0], C[1], R, 0, 2 * Math.PI); ctx.stroke();
        ctx.fillStyle = '#333'; ctx.beginPath();
        ctx.arc(P[0], P[1], Math.max(2, R * PLATE / ARM), 0, 2 * Math.PI); ctx.fill();
      }
    });
    line(ctx, m, v(f, 19), v(f, 22), '#2ca02c', 3);
    ctx.fillStyle = '#000'; ctx.font = '12px sans-serif';
    ctx.fillText(b === 2 ? 'side view (x right, z up)' : 'top view (x right, y up)', 8, 14);
  }
  function tasksAt(t) { let s = cur.tasks[0]; for (const x of cur.tasks) if (x[0] <= t) s = x; return s; }
  function draw() {
    const f = cur.frames[k]; drawView(side, 0, 2, f); drawView(top, 0, 1, f);
    const s = tasksAt(f[0]);
    label.textContent = 't = ' + f[0].toFixed(2) + ' s   thrower (blue): ' + s[1] + '   catcher (red): ' + s[2];
  }
  function tick(now) {
    if (!playing) return;
    if (last !== null) {
      const t = cur.frames[k][0] + (now - last) / 1000 * parseFloat(speed.value);
      while (k < cur.frames.length - 1 && cur.frames[k + 1][0] <= t) ++k;
      if (k >= cur.frames.length - 1) { playing = false; play.textContent = 'play'; }
      slider.value = k; draw();
    }
    last = now; requestAnimationFrame(tick);
  }
  sel.onchange = () => { playing = false; play.textContent = 'play'; choose(parseInt(sel.value)); };
  slider.oninput = () => { k = parseInt(slider.value); draw(); };
  play.onclick = () => { playing = !playing; play.textContent = playing ? 'pause' : 'play';
    if (playing) { if (k >= cur.frames.length - 1) k = 0; last = null; requestAnimationFrame(tick); } };
  choose(0);
})();
"""

STYLE = """
body { font-family: sans-serif; max-width: 1100px; margin: 1em auto; color: #222; }
figure { margin: 1.5em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.9em; color: #444; max-width: 900px; }
table { border-collapse: collapse; font-size: 0.85em; } td, th { border: 1px solid #ccc; padding: 2px 6px; }
canvas { border: 1px solid #ccc; margin-right: 6px; } .controls { margin: 0.5em 0; }
"""


def page(title, summary_html, figs, extra_html, anim):
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
             f"<style>{STYLE}</style></head><body><h1>{html.escape(title)}</h1>", summary_html]
    for name, heading, caption, data in figs.items:
        b64 = base64.b64encode(data).decode("ascii")
        parts.append(f"<figure id='fig-{name}'><h2>{html.escape(heading)}</h2>"
                     f"<img alt='{html.escape(heading)}' data-file='fig_{name}.png' src='data:image/png;base64,{b64}'>"
                     f"<figcaption>{html.escape(caption)}</figcaption></figure>")
    parts.append(extra_html)
    if anim:
        blob = json.dumps(anim, separators=(",", ":")).replace("</", "<\\/")
        parts.append("<h2 id='animation'>Animation of each attempt</h2><p>From the recorded time series (50 Hz). "
                     "Blue: the thrower, red: the catcher (body across its arms, plate in black), green: the pole; "
                     "grey: the pole centre's path over the last 2 s.</p>"
                     "<div class='controls'><select id='anim-attempt'></select> <button id='anim-play'>play</button> "
                     "speed <select id='anim-speed'><option value='0.25'>0.25×</option><option value='0.5'>0.5×</option>"
                     "<option value='1' selected>1×</option><option value='2'>2×</option></select> "
                     "<input id='anim-time' type='range' min='0' max='0' value='0' style='width:50%'></div>"
                     "<div id='anim-label'></div><canvas id='anim-side' width='520' height='380'></canvas>"
                     "<canvas id='anim-top' width='520' height='380'></canvas>"
                     f"<script type='application/json' id='animation-data'>{blob}</script>"
                     f"<script>{PLAYER_JS}</script>")
    parts.append("</body></html>")
    return "".join(parts)


def summary(throws, attempts, causes):
    caught, tries = success(throws)
    lo, hi = wilson95(caught, tries)
    counts = {}
    for r in throws:
        counts[r["outcome"]] = counts.get(r["outcome"], 0) + 1
    items = [f"<li>{len(throws)} attempts: " + ", ".join(f"{html.escape(k)} {v}" for k, v in sorted(counts.items())) +
             "</li>"]
    if tries:
        items.append(f"<li><b>success rate</b>: {caught} of {tries} attempts to catch caught and balanced again for "
                     f"3 s: <b>{100.0 * caught / tries:.1f}%</b> (95% confidence interval {100 * lo:.1f}–"
                     f"{100 * hi:.1f}%, Wilson)</li>")
    impacts = [r for r in throws if number(r, "catch_height_m", -1.0) > 0 and r["outcome"] in ("caught", "dropped")]
    if impacts:
        e = sum(abs(number(r, "energy_error_J", 0.0)) for r in impacts) / len(impacts)
        fl = sum(number(r, "flight_s", 0.0) for r in impacts) / len(impacts)
        items.append(f"<li>pole energy right after the impact within {e:.4f} J of E* on average (the paper: 0.0102 J); "
                     f"free flight {fl:.3f} s on average (the paper: 0.812 s)</li>")
    if causes:
        items.append("<li>failures by cause: " + ", ".join(f"{html.escape(c)} {n}" for c, n in
                                                           sorted(causes.items(), key=lambda x: -x[1])) + "</li>")
    if attempts:
        items.append(f"<li>time series of {len(attempts)} attempt(s) (attempt_&lt;n&gt;.csv): "
                     "<a href='#animation'>animation</a></li>")
    return "<ul>" + "".join(items) + "</ul>"


def main(argv):
    if len(argv) != 2 or argv[1].startswith("-"):
        print("usage: make_report.py DIR  (DIR as written by hil fly --out DIR or hil campaign --out DIR)",
              file=sys.stderr)
        return 2
    out_dir = argv[1]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("make_report.py: matplotlib is missing: install the Debian package python3-matplotlib",
              file=sys.stderr)
        return NO_MATPLOTLIB
    try:
        throws = read_csv(os.path.join(out_dir, "throws.csv"))
        attempts = {n: read_csv(p) for n, p in attempt_files(out_dir).items()}
    except (OSError, csv.Error) as e:
        print(f"make_report.py: cannot read {out_dir}: {e}", file=sys.stderr)
        return 1
    campaign = bool(parameter_keys(throws))
    figs = Figures(plt, out_dir)
    figure_throw(plt, figs, attempts, throws)
    figure_catch(plt, figs, attempts, throws)
    figure_heights(plt, figs, throws, attempts)
    figure_travel_energy(plt, figs, throws)
    figure_rate(plt, figs, throws)
    causes = figure_failures(plt, figs, throws)
    title = ("hil campaign" if campaign else "hil fly") + f" — report of {os.path.basename(os.path.abspath(out_dir))}"
    anim = animation_data(attempts, throws)
    text = page(title, summary(throws, attempts, causes), figs, failure_table(throws), anim)
    path = os.path.join(out_dir, "report.html")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    print(f"report: {path} ({len(figs.items)} figures" + (f", animation of {len(anim)} attempts" if anim else "") +
          ")")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
