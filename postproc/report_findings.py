"""The report's first section: what the numbers say, one sentence per comparison, generated from
the numbers the later sections print (docs/report.md, "Findings"), with the run's context.

Rules the sentences follow:
* a comparison is "significant" only when Welch's two-sided p, Holm-adjusted over the family of
  the page's enrichment sentences (every island point against every other point: k(k − 1)
  tests for k points), is below 0.05 *and* its 95% interval excludes "no difference" (1 for the
  ratio of geometric means an enrichment is compared by, as in section 6c; 0 for a
  difference); otherwise it is "inconclusive", with the reason (N, the interval, the
  adjustment);
* fewer than 3 replicas on a side is stated as a warning before anything else;
* a tumbler with R/d_large < PATTERN_MIN_RD, or fewer than PATTERN_MIN_ITERATIONS protocol
  iterations, is called a pipeline check: no island pattern is expected there (Yu 2022 sees
  patterns at R/d_large = 17.5 after 3-6 iterations; the smallest tumbler in which this project
  measured one is bst_small, R/d_large = 8.75, docs/report.md Sec. 5b);
* points whose beds were tilted to repose angles more than TILT_TOL_DEG apart are named in a
  warning: the tilt sets where the flowing layer is cut, and Fig. 8's persistent count was
  estimated ~20% higher (+4.8 +- 4.1 particles) at beds' measured tilts than at 27 deg, under 1
  degree away (docs/validation.md, "A replication with four new beds"), so part of a
  difference between such points may be the tilt's."""
import html
import re
import tomllib

import numpy as np

if __package__:
    from .report_species import species_names
    from .report_stats import (bounded_interval, compare_values, comparison_text,
                               excludes_none, fmt_interval, holm_adjust, t_quantile)
else:  # run from postproc/report.py as a file: its directory is on sys.path
    from report_species import species_names
    from report_stats import (bounded_interval, compare_values, comparison_text, excludes_none,
                              fmt_interval, holm_adjust, t_quantile)

PATTERN_MIN_RD = 8.0
PATTERN_MIN_ITERATIONS = 3
ALPHA = 0.05
TILT_TOL_DEG = 0.3


def _scene(cf):
    try:
        return tomllib.loads(str(cf.get("scene", "")))
    except tomllib.TOMLDecodeError:
        return {}


def _get(d, dotted, default=None):
    for k in dotted.split("."):
        if not isinstance(d, dict) or k not in d:
            return default
        d = d[k]
    return d


def case_repose(cf):
    """The repose tilt beta [deg] a case ran with: its scene records the resolved value
    (protocol.repose, measured on its bed or given); NaN if the file predates that."""
    v = _get(_scene(cf), "protocol.repose")
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else np.nan


def point_repose(q):
    """Mean, min and max of the repose tilt over a point's cases (NaN where none is known)."""
    b = np.array([case_repose(cf) for cf in q["members"]], float)
    b = b[np.isfinite(b)]
    return (float(b.mean()), float(b.min()), float(b.max())) if b.size else (np.nan,) * 3


def tilt_spread_warning(pts, tol=TILT_TOL_DEG):
    """A warning (HTML) when the points' mean repose tilts span more than tol degrees, naming
    each point's tilt; None when they agree or fewer than two points know theirs."""
    known = [(q, point_repose(q)) for q in pts]
    known = [(q, r) for q, r in known if np.isfinite(r[0])]
    if len(known) < 2:
        return None
    means = [r[0] for _, r in known]
    spread = max(means) - min(means)
    if spread <= tol:
        return None
    each = "; ".join(f"{html.escape(q['short'])} {r[0]:.2f}° ({r[1]:.2f}–{r[2]:.2f})"
                     for q, r in known)
    return (f"<b>Warning: the points were tilted to repose angles {spread:.2f}° apart</b> "
            f"(mean β per point, range over its cases: {each}). The tilt sets where the "
            f"flowing layer is cut; Fig. 8's persistent count was estimated ~20% higher at beds' "
            f"measured tilts than at 27°, under 1° away (docs/validation.md), so a difference "
            f"between these points may be partly the tilt's. "
            f"To compare at one tilt, set <code>protocol.repose</code> to a number in the "
            f"campaign's overrides.")


def campaign_context(c, pts):
    """What a reader needs to judge the numbers of campaign c: scene, tier, particles,
    R/d_large, iterations, rpm, the Δψ lag, replicas per point, the averaging window."""
    members = [m for q in pts if q["camp"] is c for m in q["members"]]
    ctx = dict(name=c["name"], scene="?", tier="?", particles=None, large=None, rd=None,
               iterations=None, rpm=None, lag=None, grid=None, window=None,
               replicas=sorted({len(q["members"]) for q in pts if q["camp"] is c}))
    if not members:
        return ctx
    cf = members[0]
    sc = _scene(cf)
    try:  # the campaign file names the scene file; the case's scene.name is the case's own
        scene_file = tomllib.loads(c.get("toml", "")).get("campaign", {}).get("scene", "")
    except tomllib.TOMLDecodeError:
        scene_file = ""
    ctx["scene"] = (scene_file.rsplit("/", 1)[-1].removesuffix(".toml") if scene_file
                    else _get(sc, "scene.name", "?"))
    ctx["tier"] = str(cf.get("tier", "?")) or "?"
    R, dl = _get(sc, "tumbler.radius"), _get(sc, "particles.d_large")
    if R and dl:
        ctx["rd"] = float(R) / float(dl)
    ctx["iterations"] = _get(sc, "protocol.iterations")
    ctx["rpm"] = _get(sc, "protocol.rpm")
    m = re.search(r"(?:^|;)k=([0-9.eE+-]+)", str(cf.get("collect", "")))
    ctx["lag"] = float(m.group(1)) if m else None
    ctx["grid"] = int(np.ravel(cf.get("grid_n", [0]))[0]) or None
    w0, w1 = cf.get("window_first_iteration"), cf.get("window_last_iteration")
    if w0 is not None and w1 is not None:
        ctx["window"] = (float(np.ravel(w0)[0]), float(np.ravel(w1)[0]))
    snaps = cf.get("snapshots") or []
    if snaps:
        import h5py
        with h5py.File(snaps[0], "r") as f:
            sp = f["species"][:]
        ctx["particles"], ctx["large"] = int(len(sp)), int(np.sum(sp == 1))
    # Species 1 by the name the campaign's files give it ("heavy" in a density bed of equal sizes).
    ctx["species_1"] = species_names([q for q in pts if q["camp"] is c])[1]
    return ctx


def context_line(ctx):
    def g(x, f="{:g}"):
        return "?" if x is None else f.format(x)
    reps = "–".join(str(r) for r in (ctx["replicas"][:1] + ctx["replicas"][-1:]
                                      if len(ctx["replicas"]) > 1 else ctx["replicas"])) or "?"
    parts = [f"scene {ctx['scene']}", f"tier {ctx['tier']}",
             (f"{ctx['particles']:,} particles ({ctx['large']} {ctx.get('species_1', 'large')})"
              if ctx["particles"]
              else "particles: no snapshot"),
             f"R/d_large = {g(ctx['rd'], '{:.3g}')}",
             f"{g(ctx['iterations'])} protocol iteration(s) at {g(ctx['rpm'])} rpm",
             f"Δψ lag {g(ctx['lag'])} iteration", f"{g(ctx['grid'])} × {g(ctx['grid'])} grid"]
    if ctx["window"]:
        parts.append(f"maps averaged over iterations {ctx['window'][0]:g}–{ctx['window'][1]:g}")
    parts.append(f"{reps} replica(s) per point")
    return f"{ctx['name']}: " + ", ".join(parts)


def ci_span(b, digits=3, n=True):
    """A bounded_interval as HTML: the text of fmt_interval in a span that names the quantity's
    bounds (data-lo, data-hi), so the page can be checked for intervals that leave them
    (tests/analysis/check_report_chromium.py)."""
    text = html.escape(fmt_interval(b, digits, n))
    if not np.isfinite(b["lower"]):  # no interval printed (N < 2 or no mean)
        return text
    lo = "-inf" if b.get("lo") is None else f"{b['lo']:g}"
    hi = "inf" if b.get("hi") is None or not np.isfinite(b["hi"]) else f"{b['hi']:g}"
    return f'<span class="ci" data-lo="{lo}" data-hi="{hi}">{text}</span>'


def p_text(p):
    """'p = 0.012' or 'p < 0.001' ('p = –' untested), for a sentence."""
    return "p = –" if not np.isfinite(p) else (f"p = {p:.2g}" if p >= 1e-3 else "p < 0.001")


def mapped_name(P):
    """The species P's enrichment counts, as analysis.h5 names it ("large", or "light" in a
    density-bidisperse bed); "large" where the file predates the names."""
    a = P["an"]["attrs"] if P.get("an") else {}
    k = a.get("mapped_species")
    name = a.get(f"species_{int(np.ravel(k)[0])}") if k is not None else None
    return str(name) if name else "large"


def enrichment_sentences(pts):
    """One sentence (HTML) per (island point P, other point Q of its campaign): P's enrichment on
    its own islands against Q's on the same mask; and the numbers as CSV rows."""
    out, rows, tests = [], [], []
    for P in pts:
        if P["an"] is None or not P["islands"]:
            continue
        own = P["an"].get("enrichment_vs", {}).get(P["pid"])
        if not own:
            continue
        pe = bounded_interval(own["values"], 0.0, np.inf)
        pname = html.escape(P["short"])
        others = [Q for Q in pts if Q is not P and Q["camp"] is P["camp"]
                  and (Q["an"] or {}).get("enrichment_vs", {}).get(P["pid"])]
        if not others:
            verdict = ("its interval includes 1 (no preference shown)"
                       if pe["n"] >= 2 and pe["lower"] <= 1 <= pe["upper"] else
                       "more than their share" if pe["n"] >= 2 and pe["lower"] > 1 else
                       "less than their share" if pe["n"] >= 2 else "one replica: no interval")
            out.append(f"{pname} concentrates {mapped_name(P)} particles in its CM islands "
                       f"{ci_span(pe)} times the islands' share of the view: "
                       f"{html.escape(verdict)}.")
            continue
        for Q in others:
            qv = Q["an"]["enrichment_vs"][P["pid"]]["values"]
            # The ratio of geometric means, as section 6c compares every enrichment (a replica
            # at 0: the difference of the means).
            tests.append((P, Q, pe, bounded_interval(qv, 0.0, np.inf),
                          compare_values(own["values"], qv, 0.0, np.inf)))
    # Holm over every comparison on the page: with k island points each against the others, a
    # raw p < 0.05 would call some pair "significant" by chance in a large campaign.
    holm = holm_adjust([c["p"] for *_, c in tests]) if tests else []
    n_tested = int(np.isfinite(np.asarray(holm, float)).sum()) if tests else 0
    for (P, Q, pe, qe, c), p_holm in zip(tests, holm):
        pname = html.escape(P["short"])
        sig = np.isfinite(p_holm) and p_holm < ALPHA and excludes_none(c)
        n_min = min(c["na"], c["nb"])
        if sig:
            more = c["est"] > (1.0 if c["kind"] == "ratio" else 0.0)
            verdict = f"significantly {'more' if more else 'less'}"
        else:
            why = []
            if n_min < 3:
                why.append(f"N = {n_min}")
            if np.isfinite(c["lower"]):
                if not excludes_none(c):
                    why.append(f"the interval of the {c['kind']} includes "
                               f"{'1' if c['kind'] == 'ratio' else '0'}")
                elif np.isfinite(p_holm):
                    why.append(f"not below {ALPHA:g} once adjusted for the {n_tested} "
                               "comparisons (Holm)")
                else:
                    why.append("no test (the replicas do not vary)")
            else:
                why.append("no interval (fewer than 2 replicas)")
            if pe["n"] >= 2 and pe["lower"] <= 1 <= pe["upper"]:
                why.append(f"{pname}'s own interval includes 1")
            verdict = "inconclusive: " + ", ".join(why)
        how = ("ratio of the geometric means" if c["kind"] == "ratio" else "difference")
        holm_text = f", Holm-adjusted {p_text(p_holm)[2:]}" if n_tested > 1 else ""
        test = (f"Welch 95% on the logarithms, {p_text(c['p'])}{holm_text}" if c["kind"] == "ratio"
                else f"Welch 95%, {p_text(c['p'])}{holm_text}")
        cmp_text = f"{how} {comparison_text(c)}" + (f" ({test})" if np.isfinite(c["p"]) else "")
        out.append(f"<b>{pname}</b> concentrates {mapped_name(P)} particles in its CM islands "
                   f"{ci_span(pe)} times the islands' share of the view, "
                   f"<b>{html.escape(Q['short'])}</b> {ci_span(qe)} on the same mask; "
                   f"{html.escape(cmp_text)}: <b>{html.escape(verdict)}</b>.")
        rows.append([P["label"], Q["label"], pe["mean"], pe["lower"], pe["upper"],
                     qe["mean"], qe["lower"], qe["upper"], c["kind"], c["est"], c["lower"],
                     c["upper"], c["p"], p_holm, "significant" if sig else "inconclusive"])
    return out, rows


def mixing_sentence(q):
    """The final mixing index of a point against a random bed of the same particles."""
    mx = q.get("mixing")
    if not mx or not mx["excess"]:
        return None
    obs = bounded_interval(mx["observed"], 0.0, 1.0)
    rnd = float(np.mean(mx["random"]))
    ex = np.asarray(mx["excess"], float)
    n = len(ex)
    if n >= 2:
        half = t_quantile(0.975, n - 1) * ex.std(ddof=1) / np.sqrt(n)
        m = ex.mean()
        if m - half > 0:
            verdict = "more segregated than a random mix"
        elif m + half < 0:
            verdict = "more even than a random mix"
        else:
            verdict = "indistinguishable from a random mix"
        ex_s = f"excess {m:+.2g} ± {half:.2g}"
    else:
        verdict, ex_s = "one replica: no interval", f"excess {ex.mean():+.2g}"
    return (f"{html.escape(q['short'])}: mixing index at the last snapshot {ci_span(obs)}; a "
            f"random bed of the same particles gives {rnd:.3g}; {html.escape(ex_s)}: "
            f"<b>{verdict}</b>.")


def pipeline_check(ctx):
    """The sentence that says no pattern is expected, from R/d_large and the iterations."""
    why = []
    if ctx["rd"] is not None and ctx["rd"] < PATTERN_MIN_RD:
        why.append(f"R/d_large = {ctx['rd']:.3g} &lt; {PATTERN_MIN_RD:g}")
    it = ctx["iterations"]
    if it is not None and float(it) < PATTERN_MIN_ITERATIONS:
        why.append(f"{float(it):g} protocol iteration(s) &lt; {PATTERN_MIN_ITERATIONS}")
    if not why:
        return None
    return (f"<b>{html.escape(ctx['name'])} ({html.escape(ctx['scene'])}) is a pipeline check</b> ({', '.join(why)}): no island "
            f"pattern is expected in it (Yu 2022 sees them at R/d_large = 17.5 after 3-6 "
            f"iterations; this project measured one at R/d_large = 8.75, docs/report.md Sec. "
            f"5b), so its numbers test the chain of analyses, not the physics.")
