//! The chooser against scripted worlds: what each candidate costs and
//! draws per frame, measurements arriving late.

use super::*;

/// noc, vfc, hzb, hroc.
fn chooser() -> Chooser {
    let warm = WarmUp { cold: 2, handed: 1, cold_frustum: false };
    Chooser::new(vec![Load::All, Load::Frustum, Load::Occluded, Load::Occluded], vec![WarmUp::NONE, WarmUp::NONE, warm, warm], Params::default())
}

/// noc, vfc, hzb, hroc with `auto`'s warm-ups: `hzb`'s frames from
/// nothing draw the frustum, HROC's are reseeded.
fn chooser_as_auto() -> Chooser {
    let warm = vec![WarmUp::NONE, WarmUp::NONE, WarmUp { cold: 2, handed: 0, cold_frustum: true }, WarmUp { cold: 2, handed: 1, cold_frustum: false }];
    Chooser::new(vec![Load::All, Load::Frustum, Load::Occluded, Load::Occluded], warm, Params::default())
}

/// Runs `frames` frames of a world where candidate i costs `cost(i,
/// frame)` and draws `draws(i)` triangles, measurements arriving
/// `late` frames after; returns the candidate of every frame.
fn run(c: &mut Chooser, frames: u64, late: u64, cost: impl Fn(usize, u64) -> f64, draws: impl Fn(usize) -> f64, frustum: f64, all: f64) -> Vec<usize> {
    decisions(c, frames, late, cost, draws, frustum, all).iter().map(|d| d.candidate).collect()
}

/// [`run`]'s decisions.
fn decisions(c: &mut Chooser, frames: u64, late: u64, cost: impl Fn(usize, u64) -> f64, draws: impl Fn(usize) -> f64, frustum: f64, all: f64) -> Vec<Decision> {
    decisions_in(c, frames, late, cost, |i, _| draws(i), |_| frustum, all, |_| false)
}

/// [`decisions`] in a world where candidate i draws `draws(i, frame)`
/// triangles, the frustum holds `frustum(frame)`, and `cut(frame)` is a
/// camera cut.
#[allow(clippy::too_many_arguments)]
fn decisions_in(
    c: &mut Chooser,
    frames: u64,
    late: u64,
    cost: impl Fn(usize, u64) -> f64,
    draws: impl Fn(usize, u64) -> f64,
    frustum: impl Fn(u64) -> f64,
    all: f64,
    cut: impl Fn(u64) -> bool,
) -> Vec<Decision> {
    let mut ran: Vec<Decision> = Vec::new();
    for f in 0..frames {
        if f >= late {
            let d = ran[(f - late) as usize];
            let g = f - late;
            let o = Observation {
                candidate: d.candidate,
                frame: g,
                cost_ms: cost(d.candidate, g),
                triangles: draws(d.candidate, g),
                frustum_triangles: frustum(g),
                warm_up: !d.measured,
                handed: d.from.is_some(),
            };
            c.observe_frame(&o, all, d.first);
        }
        if cut(f) {
            c.cut();
        }
        ran.push(c.decide(f, frustum(f), all));
    }
    ran
}

/// Share of `ds` that ran candidate `m`.
fn share(ds: &[Decision], m: usize) -> f64 {
    ds.iter().filter(|d| d.candidate == m).count() as f64 / ds.len() as f64
}

#[test]
fn it_settles_on_the_cheapest_and_probes_rarely() {
    let mut c = chooser();
    // hroc (3) cheapest, hzb close behind, vfc and noc far.
    let cost = |i: usize, _| [40.0, 30.0, 12.0, 10.0][i];
    let draws = |i: usize| [1e6, 5e5, 5e4, 3e4][i];
    let ran = run(&mut c, 600, 2, cost, draws, 5e5, 1e6);
    let tail = &ran[100..];
    let on_best = tail.iter().filter(|&&i| i == 3).count() as f64 / tail.len() as f64;
    assert!(on_best > 0.93, "{on_best}");
    // One frame in thirty, the calibration's aside.
    assert!(c.probe_frames.saturating_sub(7) * 30 <= 600, "{} probe frames", c.probe_frames);
}

#[test]
fn the_calibration_ends_with_one_switch() {
    // A small scene: vfc (1) cheapest, hroc (3) the calibration's first.
    // Once vfc has run, the calibration's last probe, hroc does not run
    // again for a frame before the choice.
    for late in [1, 2, 3] {
        let mut c = chooser();
        let ran = run(&mut c, 40, late, |i, _| [4.2, 4.0, 7.0, 8.0][i], |i| [5600.0, 800.0, 300.0, 120.0][i], 800.0, 5600.0);
        let first_vfc = ran.iter().position(|&i| i == 1).expect("vfc runs");
        assert!(ran[first_vfc..].iter().all(|&i| i <= 1), "late {late}: {ran:?}");
    }
}

#[test]
fn noc_is_never_tried_where_an_optimistic_guess_is_far_off() {
    let mut c = chooser();
    let cost = |i: usize, _| [400.0, 30.0, 12.0, 10.0][i];
    let draws = |i: usize| [1e7, 5e5, 5e4, 3e4][i];
    run(&mut c, 400, 2, cost, draws, 5e5, 1e7);
    assert_eq!(c.frames_run[0], 0);
}

#[test]
fn it_follows_a_change_and_does_not_oscillate_between_equals() {
    let mut c = chooser();
    // vfc cheapest for 300 frames, then hroc; hzb and noc never.
    let cost = |i: usize, f: u64| match (i, f < 300) {
        (1, true) => 10.0,
        (3, true) => 14.0,
        (1, false) => 20.0,
        (3, false) => 9.0,
        (0, _) => 25.0,
        _ => 30.0,
    };
    let draws = |i: usize| [1e5, 8e4, 2e4, 1e4][i];
    let ran = run(&mut c, 700, 3, cost, draws, 8e4, 1e5);
    let share = |r: &[usize], m: usize| r.iter().filter(|&&i| i == m).count() as f64 / r.len() as f64;
    assert!(share(&ran[50..300], 1) > 0.9, "{}", share(&ran[50..300], 1));
    assert!(share(&ran[450..], 3) > 0.9, "{}", share(&ran[450..], 3));
    // Two equal candidates with noise: few switches.
    let mut c = chooser();
    let noisy = |i: usize, f: u64| [50.0, 10.0, 50.0, 10.0][i] * (1.0 + 0.05 * ((f * 7919 % 13) as f64 / 13.0 - 0.5));
    let ran = run(&mut c, 600, 2, noisy, |i| [1e5, 5e4, 5e4, 5e4][i], 5e4, 1e5);
    let switches = ran.windows(2).filter(|w| w[0] != w[1]).count();
    // Probes cost two switches each; beyond them, at most a few.
    assert!(switches as u64 <= 2 * (c.probe_frames + 4), "{switches} switches, {} probe frames", c.probe_frames);
}

#[test]
fn bounds_predict_until_measured_and_unplausible_never_runs() {
    let mut c = chooser();
    // hzb's warm-up frames drew the frustum at 40 ms: vfc's bound.
    c.bound(1, 0, 40.0);
    assert_eq!(c.predict(1, 5e5, 1e7), (40.0, true));
    // vfc is cheaper (10 ms): with the bound alone it is still tried
    // (40 is within the plausible factor of hroc's 35) and then chosen.
    let cost = |i: usize, _| [400.0, 10.0, 45.0, 35.0][i];
    let draws = |i: usize| [1e7, 5e5, 5e4, 3e4][i];
    let ran = run(&mut c, 1500, 2, cost, draws, 5e5, 1e7);
    let on_vfc = ran[100..].iter().filter(|&&i| i == 1).count() as f64 / (ran.len() - 100) as f64;
    assert!(on_vfc > 0.9, "{on_vfc}");
    // noc, never plausible, is never forced either (1500 > forced frames).
    assert_eq!(c.frames_run[0], 0);
}

#[test]
fn a_switch_to_a_candidate_that_draws_more_needs_twice_the_margin() {
    // hzb (2) draws ten times what hroc (3) does; vfc and noc far off.
    let share = |hzb_ms: f64| {
        let mut c = chooser();
        let cost = move |i: usize, _| [40.0, 30.0, hzb_ms, 10.0][i];
        let ran = run(&mut c, 400, 2, cost, |i| [1e6, 5e5, 1e4, 1e3][i], 5e5, 1e6);
        ran[50..].iter().filter(|&&i| i == 2).count() as f64 / (ran.len() - 50) as f64
    };
    // 10 % cheaper: within twice the margin, hroc stays.
    assert!(share(9.0) < 0.05, "{}", share(9.0));
    // 20 % cheaper: hzb takes over.
    assert!(share(8.0) > 0.9, "{}", share(8.0));
}

#[test]
fn an_old_estimate_is_probed_before_a_switch_to_it() {
    let mut c = chooser();
    // hroc (3) cheapest; from frame 200 the view costs every candidate
    // twice as much, which only the running hroc's estimate sees.
    let cost = |i: usize, f: u64| [40.0, 30.0, 12.0, 10.0][i] * if f < 200 { 1.0 } else { 2.0 };
    let ds = decisions(&mut c, 400, 2, cost, |i| [1e6, 5e5, 5e4, 5e4][i], 5e5, 1e6);
    // hzb runs after it only in probes: no switch on its stale 12 ms.
    let switched = ds[200..].iter().filter(|d| d.candidate != 3 && !d.probe).count();
    assert_eq!(switched, 0, "{:?}", ds[200..].iter().map(|d| d.candidate).collect::<Vec<_>>());
}

#[test]
fn a_candidate_taking_over_starts_from_the_last_visible_set_unless_a_cut_came() {
    let mut c = chooser();
    c.set_params(Params {
        margin: 0.0,
        confirm: 1,
        dwell: 0,
        probe_every: 2,
        stale: 2,
        plausible: f64::INFINITY,
        forced: 4,
        cut_probe_every: 2,
        probe_share: 1.0,
        ..Params::default()
    });
    let cost = |i: usize, f: u64| [14.0, 12.0, 11.0, 10.0][i] * (1.0 + 0.3 * ((f * 7919 % 13) as f64 / 13.0));
    // hzb (2) draws twice hroc's (3) share: hroc resumes from its own set.
    let draws = |i: usize| [1e5, 1e5, 2e4, 1e4][i];
    let (mut sets, mut ds): ([Option<u64>; 4], Vec<Decision>) = ([None; 4], Vec::new());
    for f in 0..300u64 {
        if let Some(d) = f.checked_sub(1).map(|g| ds[g as usize]) {
            let o = Observation {
                candidate: d.candidate,
                frame: f - 1,
                cost_ms: cost(d.candidate, f - 1),
                triangles: draws(d.candidate),
                frustum_triangles: 1e5,
                warm_up: !d.measured,
                handed: d.from.is_some(),
            };
            c.observe(&o);
        }
        if f % 37 == 36 {
            c.cut();
            sets = [None; 4];
        }
        let d = c.decide(f, 1e5, 2e5);
        let recent = |i: usize| sets[i].filter(|&h| f <= h + ARRIVAL);
        let last = (2..4).filter_map(|i| recent(i).map(|h| (h, i))).max().map(|(_, i)| i);
        let own = (d.candidate == 3 && recent(3).is_some()).then_some(3);
        let want = own.or(last).filter(|_| d.fresh && d.candidate >= 2);
        assert_eq!(d.from, want, "frame {f}: {d:?}");
        if d.candidate >= 2 {
            sets[d.candidate] = Some(f);
        }
        ds.push(d);
    }
    // Handed over, resumed after a stateless probe, and started cold.
    assert!(ds.iter().any(|d| d.from.is_some_and(|h| h != d.candidate)));
    assert!(ds.iter().any(|d| d.from == Some(d.candidate)));
    assert!(ds.iter().skip(1).any(|d| d.fresh && d.candidate >= 2 && d.from.is_none()));
}

#[test]
fn a_candidate_resumes_from_its_own_set_where_the_one_handed_is_larger() {
    // hroc (3) runs, drawing a fifth of hzb's (2) share; probes of hzb
    // (every 30 frames) start from hroc's set, and hroc, back after each,
    // from its own: hzb's set would have it draw what it culled.
    let mut c = chooser_as_auto();
    let cost = |i: usize, _| [40.0, 30.0, 11.0, 10.0][i];
    let ds = decisions(&mut c, 400, 2, cost, |i| [1e6, 5e5, 5e4, 1e4][i], 5e5, 1e6);
    let ds = &ds;
    let after = |m: usize| (100..400).filter(move |&f| ds[f].fresh && ds[f].candidate == m && ds[f - 1].candidate != m);
    let (hzb, hroc): (Vec<usize>, Vec<usize>) = (after(2).collect(), after(3).filter(|&f| ds[f - 1].candidate == 2).collect());
    assert!(!hzb.is_empty() && !hroc.is_empty(), "{:?}", ds.iter().map(|d| d.candidate).collect::<Vec<_>>());
    assert!(hzb.iter().all(|&f| ds[f].from == Some(3)), "{:?}", hzb.iter().map(|&f| ds[f]).collect::<Vec<_>>());
    assert!(hroc.iter().all(|&f| ds[f].from == Some(3)), "{:?}", hroc.iter().map(|&f| ds[f]).collect::<Vec<_>>());
}

#[test]
fn hzb_from_nothing_hands_over_no_visible_set() {
    // hzb (2) runs; at a cut at frame 100 its frames from nothing draw
    // the frustum at `vfc`'s 30 ms, which prices cuts into its prediction,
    // and hroc (3) is checked by a probe a frame later, while hzb still
    // warms up (the switch at the cut itself left out). hzb's set then is
    // the whole frustum: hroc starts from nothing, reseeded.
    let mut c = chooser_as_auto();
    c.set_params(Params { margin: 0.05, confirm: 2, dwell: 0, isolated_cuts: 0.0, ..Params::default() });
    let cost = |i: usize, f: u64| if i == 2 && (100..102).contains(&f) { 30.0 } else { [60.0, 30.0, 10.0, 11.0][i] };
    let ds = decisions_in(&mut c, 104, 1, cost, |i, _| [1e6, 5e5, 5e4, 6e4][i], |_| 5e5, 1e6, |f| f == 100);
    assert!(ds[90..101].iter().all(|d| d.candidate == 2), "{:?}", ds.iter().map(|d| d.candidate).collect::<Vec<_>>());
    assert!(ds[101].candidate == 3 && ds[101].fresh && ds[101].from.is_none(), "{:?}", &ds[100..]);
}

#[test]
fn the_triangle_cost_is_fitted_within_candidates() {
    let mut c = chooser();
    // cost = 2 + 1e-4 * T for vfc, 5 + 1e-4 * T for hroc.
    for f in 0..20u64 {
        let t = 1e4 * (1 + f % 5) as f64;
        c.observe(&Observation { candidate: 1, frame: f, cost_ms: 2.0 + 1e-4 * t, triangles: t, frustum_triangles: t, warm_up: false, handed: false });
        c.observe(&Observation { candidate: 3, frame: f, cost_ms: 5.0 + 1e-4 * t * 0.2, triangles: t * 0.2, frustum_triangles: t, warm_up: false, handed: false });
    }
    assert!((c.triangle_ms() - 1e-4).abs() < 1e-6, "{}", c.triangle_ms());
    // vfc with twice the frustum: 2 + 1e-4 * 2e5 = 22 ms.
    let (p, measured) = c.predict(1, 2e5, 4e5);
    assert!(measured && (p - 22.0).abs() < 0.1, "{p}");
}

#[test]
fn a_slope_the_frames_do_not_establish_is_zero() {
    // vfc's frames cost 4 ms give or take 1.5 whatever they draw (750 to
    // 830 triangles): no slope, where a least-squares fit alone finds one.
    let mut c = chooser();
    let (mut tc, mut tt, mut mt, mut mc) = (0.0, 0.0, 0.0, 0.0);
    let frames: Vec<(f64, f64)> = (0..40u64).map(|f| (750.0 + 2.0 * f as f64, 4.0 + 1.5 * ((f * 7919 % 13) as f64 / 6.0 - 1.0))).collect();
    for (f, &(t, ms)) in frames.iter().enumerate() {
        c.observe(&Observation { candidate: 1, frame: f as u64, cost_ms: ms, triangles: t, frustum_triangles: t, warm_up: false, handed: false });
    }
    let recent = &frames[frames.len() - 10..];
    for &(t, ms) in recent {
        mt += t / recent.len() as f64;
        mc += ms / recent.len() as f64;
    }
    for &(t, ms) in recent {
        tc += (t - mt) * (ms - mc);
        tt += (t - mt) * (t - mt);
    }
    assert!((tc / tt).abs() > 1e-3, "the noise fits a slope: {}", tc / tt);
    assert_eq!(c.triangle_ms(), 0.0);
}

#[test]
fn an_occlusion_method_dearer_drawing_nothing_is_not_probed_after_a_change_of_view() {
    // A small scene: hroc's frame (8 ms) costs more than vfc's whole
    // frame (4) on any view, and the frustum holds four times more
    // triangles from frame 100, noise on every frame.
    let frustum = |f: u64| (if f < 100 { 800.0 } else { 3200.0 }) * (1.0 + 0.02 * (f % 5) as f64);
    let draws = move |i: usize, f: u64| match i {
        0 => 5600.0,
        2 | 3 => 0.3 * frustum(f),
        _ => frustum(f),
    };
    let cost = |i: usize, f: u64| [4.2, 4.0, 7.0, 8.0][i] + 1.5 * ((f * 7919 % 13) as f64 / 6.0 - 1.0);
    let mut c = chooser();
    let ds = decisions_in(&mut c, 200, 2, cost, draws, frustum, 5600.0, |_| false);
    let probed = ds[100..].iter().filter(|d| d.candidate >= 2).count();
    assert_eq!(probed, 0, "{:?}", ds[100..].iter().map(|d| d.candidate).collect::<Vec<_>>());
}

#[test]
fn a_cut_has_an_occlusion_method_probed_while_vfc_runs() {
    // vfc (1) cheapest until a cut at frame 200, after which hroc (3)
    // costs half of it; nothing else tells the chooser.
    let cost = |i: usize, f: u64| if f < 200 { [40.0, 10.0, 16.0, 14.0][i] } else { [40.0, 10.0, 7.0, 5.0][i] };
    let draws = |i: usize, _| [1e6, 5e5, 5e4, 5e4][i];
    assert_probed_after_cut(cost, draws, 300, 200, 1, 3);
}

/// In a world of `cost` and `draws` (frustum 5e5 of 1e6 triangles) with
/// a camera cut at frame `cut`: candidate `before` runs from frame 50 to
/// the cut and `after` from 20 frames after it on, which without probes
/// after cuts it does not (the estimate from before the cut holds on).
fn assert_probed_after_cut(cost: impl Fn(usize, u64) -> f64 + Copy, draws: impl Fn(usize, u64) -> f64 + Copy, frames: u64, cut: u64, before: usize, after: usize) {
    let share_after = |params: Params| {
        let mut c = chooser();
        c.set_params(params);
        let ds = decisions_in(&mut c, frames, 2, cost, draws, |_| 5e5, 1e6, |f| f == cut);
        let ran = (cut - 50) as usize..cut as usize;
        assert!(share(&ds[ran.clone()], before) > 0.9, "{}", share(&ds[ran], before));
        share(&ds[(cut + 20) as usize..], after)
    };
    assert!(share_after(Params::default()) > 0.9, "{}", share_after(Params::default()));
    // Without probes after cuts (nor the stale estimate's probe after
    // `probe_every` frames, which finds it in the end).
    let never = Params { cut_probe_every: u64::MAX, probe_every: 1000, ..Params::default() };
    assert!(share_after(never) < 0.5, "{}", share_after(never));
}

#[test]
fn a_frustum_holding_three_times_the_triangles_changes_the_view_as_a_cut_does() {
    // hroc (3) draws the whole frustum until frame 200 (the eye inside a
    // box), then a tenth of it while the frustum holds five times more:
    // its share learnt before predicts it dear.
    let frustum = |f: u64| if f < 200 { 1e5 } else { 5e5 };
    let draws = |i: usize, f: u64| match i {
        0 => 1e6,
        3 if f >= 200 => 1e4,
        _ => frustum(f),
    };
    let cost = move |i: usize, f: u64| [8.0, 2.0, 6.0, 4.0][i] + 1e-4 * draws(i, f);
    let hroc_after = |params: Params| {
        let mut c = chooser();
        c.set_params(params);
        let ds = decisions_in(&mut c, 300, 2, cost, draws, frustum, 1e6, |_| false);
        share(&ds[220..], 3)
    };
    assert!(hroc_after(Params::default()) > 0.9, "{}", hroc_after(Params::default()));
    let never = Params { view_change: f64::INFINITY, ..Params::default() };
    assert!(hroc_after(never) < 0.5, "{}", hroc_after(never));
}

#[test]
fn with_a_camera_cut_every_frame_it_still_switches() {
    // hroc (3) cheapest until frame 100, then vfc (1) at half its cost;
    // every frame a cut, so every estimate is from another view and a
    // switch is checked by a probe, whose measurement then stands.
    let cost = |i: usize, f: u64| if f < 100 { [40.0, 10.0, 8.0, 6.0][i] } else { [40.0, 5.0, 12.0, 10.0][i] };
    let mut c = chooser();
    let ds = decisions_in(&mut c, 300, 2, cost, |i, _| [1e6, 5e5, 5e4, 5e4][i], |_| 5e5, 1e6, |_| true);
    assert!(share(&ds[50..100], 3) > 0.8, "{}", share(&ds[50..100], 3));
    assert!(share(&ds[130..], 1) > 0.8, "{}", share(&ds[130..], 1));
}

#[test]
fn an_occlusion_method_running_through_a_cut_prices_it_as_a_cold_start() {
    // hroc (3) cheapest; after the cut at frame 100 it reseeds and its
    // next two frames cost 14 ms, not 4.
    let cost = |i: usize, f: u64| if i == 3 && (100..102).contains(&f) { 14.0 } else { [40.0, 10.0, 8.0, 4.0][i] };
    let mut c = chooser();
    let ds = decisions_in(&mut c, 120, 2, cost, |i, _| [1e6, 5e5, 5e4, 3e4][i], |_| 5e5, 1e6, |f| f == 100);
    assert!(ds[90..].iter().all(|d| d.candidate == 3), "{:?}", ds[90..].iter().map(|d| d.candidate).collect::<Vec<_>>());
    // Its cold frames are left out of its steady estimate ...
    assert!(!ds[100].measured && !ds[101].measured && ds[102].measured);
    let steady = c.steady(3, 5e5, 1e6).0;
    assert!((steady - 4.0).abs() < 0.5, "{steady}");
    // ... and, at the recent rate of cuts, priced into its prediction.
    let predicted = c.predict(3, 5e5, 1e6).0;
    assert!(predicted > steady + 0.1, "{predicted} against {steady}");
}

#[test]
fn a_cut_has_vfc_probed_while_an_occlusion_method_runs() {
    // hroc (3) a little cheaper than vfc (1) until a cut at frame 100,
    // after which vfc costs 3 ms and hroc 8: vfc's estimate holds the
    // view before the cut, and only a probe finds it cheap.
    let cost = |i: usize, f: u64| if f < 100 { [40.0, 12.0, 16.0, 10.0][i] } else { [40.0, 3.0, 10.0, 8.0][i] };
    assert_probed_after_cut(cost, |i, _| [1e6, 5e5, 5e4, 5e4][i], 180, 100, 3, 1);
}

#[test]
fn a_probe_after_the_frustum_fills_waits_until_its_warm_up_fits_the_probes_share() {
    // A small scene: vfc (1) cheapest while hroc (3) draws most of the
    // frustum; at frame 41 the frustum holds four times the triangles,
    // of which hroc draws a tenth, and it is then the cheaper. Its share
    // learnt before predicts it dear; its probe (two cold frames) waits
    // until 4 % of the time spent covers it, then finds it.
    let frustum = |f: u64| if f < 41 { 1000.0 } else { 4000.0 };
    let draws = move |i: usize, f: u64| match i {
        0 => 8000.0,
        1 => frustum(f),
        _ if f < 41 => 0.9 * frustum(f),
        _ => 0.1 * frustum(f),
    };
    let cost = move |i: usize, f: u64| [2.0, 2.0, 5.0, 4.0][i] + 2e-3 * draws(i, f);
    let mut c = chooser();
    let ds = decisions_in(&mut c, 300, 2, cost, draws, frustum, 8000.0, |_| false);
    let ran: Vec<usize> = ds.iter().map(|d| d.candidate).collect();
    assert!(ran[20..60].iter().all(|&i| i == 1), "{ran:?}");
    assert!(share(&ds[200..], 3) > 0.9, "{ran:?}");
}

#[test]
fn an_isolated_cut_starts_the_estimates_anew() {
    // The eye inside a box until a cut at frame 100: every candidate
    // draws nearly everything at about 200 ms, hroc (3) a little less.
    // After the cut hroc costs 10 ms and hzb 11, vfc 50 and noc 60; the
    // triangles drawn do not change, the pixels do.
    let cost = |i: usize, f: u64| if f < 100 { [200.0, 195.0, 180.0, 170.0][i] } else { [60.0, 50.0, 11.0, 10.0][i] };
    let draws = |i: usize, _| [2e6, 2e6, 1.5e6, 1.3e6][i];
    let occluding_after = |params: Params| {
        let mut c = chooser();
        c.set_params(params);
        let ds = decisions_in(&mut c, 200, 2, cost, draws, |_| 2e6, 2e6, |f| f == 100);
        assert!(share(&ds[60..100], 3) > 0.9);
        share(&ds[120..], 3) + share(&ds[120..], 2)
    };
    assert!(occluding_after(Params::default()) > 0.9, "{}", occluding_after(Params::default()));
    // Estimates carried across the cut settle on vfc at five times the cost.
    let carried = Params { isolated_cuts: 0.0, ..Params::default() };
    assert!(occluding_after(carried) < 0.5, "{}", occluding_after(carried));
    // At the cut vfc is probed, then hroc's frame 101 is a warm-up from
    // nothing: measured two frames late, its 10 ms bounds hroc's estimate
    // before any steady frame of the new view is.
    let mut c = chooser();
    let ds = decisions_in(&mut c, 104, 2, cost, draws, |_| 2e6, 2e6, |f| f == 100);
    assert!(ds[101].candidate == 3 && !ds[101].measured, "{:?}", &ds[99..]);
    assert_eq!(c.steady(3, 2e6, 2e6), (10.0, true));
}

#[test]
fn an_estimate_of_one_spiky_frame_is_probed_again() {
    // vfc (1) costs 5 ms, but its one measured frame in the calibration
    // (measurements a frame late) spiked to 12: past `plausible` times
    // hroc's 8, it was not probed again.
    let cost = |i: usize, f: u64| if i == 1 && f < 10 { 12.0 } else { [40.0, 5.0, 9.0, 8.0][i] };
    let vfc_after = |params: Params| {
        let mut c = chooser();
        c.set_params(params);
        let ds = decisions_in(&mut c, 300, 1, cost, |i, _| [1e6, 5e5, 5e4, 3e4][i], |_| 5e5, 1e6, |_| false);
        assert_eq!(ds.iter().take(10).filter(|d| d.candidate == 1 && !d.first).count(), 1);
        share(&ds[100..], 1)
    };
    assert!(vfc_after(Params::default()) > 0.9, "{}", vfc_after(Params::default()));
    let once = Params { plausible_once: Params::default().plausible, ..Params::default() };
    assert!(vfc_after(once) < 0.1, "{}", vfc_after(once));
}

/// The eye inside boxes until a camera cut at frame 60, `after`
/// triangles in the frustum then: the frustum's triangles, and what each
/// candidate draws (`noc` the scene's 1e6, the others the whole frustum).
/// Inside the boxes the frustum holds 8e5 or 1e6 triangles, frame by
/// frame, at the same cost: what a frame costs there is its pixels.
fn boxes_until_a_cut(after: f64) -> (impl Fn(u64) -> f64 + Copy, impl Fn(usize, u64) -> f64 + Copy) {
    let frustum = move |f: u64| match f {
        0..60 if f.is_multiple_of(2) => 1e6,
        0..60 => 8e5,
        _ => after,
    };
    (frustum, move |i: usize, f: u64| if i == 0 { 1e6 } else { frustum(f) })
}

#[test]
fn a_cut_has_vfc_probed_while_noc_runs() {
    // The eye inside boxes until a cut at frame 60: the frustum holds
    // most of the scene, every candidate draws it, and what a frame costs
    // is its pixels, not its triangles; `noc` (0) is cheapest. After the
    // cut the frustum holds a fifth of the scene, `vfc` (1) costs a sixth
    // of `noc` and the occlusion methods more than `noc`: only a probe of
    // `vfc` finds it cheap (its estimate holds the boxes' view).
    let (frustum, draws) = boxes_until_a_cut(2e5);
    let cost = |i: usize, f: u64| if f < 60 { [40.0, 42.0, 60.0, 65.0][i] } else { [18.0, 3.0, 30.0, 30.0][i] };
    let vfc_after = |params: Params| {
        let mut c = chooser();
        c.set_params(params);
        let ds = decisions_in(&mut c, 96, 2, cost, draws, frustum, 1e6, |f| f == 60);
        assert!(share(&ds[20..60], 0) > 0.9, "{:?}", ds.iter().map(|d| d.candidate).collect::<Vec<_>>());
        share(&ds[75..], 1)
    };
    assert!(vfc_after(Params::default()) > 0.9, "{}", vfc_after(Params::default()));
    // Without probes after cuts (nor the probe of a one-frame estimate
    // after `probe_every` frames).
    let never = Params { cut_probe_every: u64::MAX, probe_every: 1000, ..Params::default() };
    assert!(vfc_after(never) < 0.1, "{}", vfc_after(never));
}

#[test]
fn a_frame_drawing_the_frustum_after_a_cut_bounds_an_estimate_from_before() {
    // The eye inside boxes until a cut at frame 60: every candidate draws
    // the frustum, what a frame costs is its pixels, and `hzb` (2) is
    // cheapest. After the cut the frustum holds a thousand triangles,
    // `hzb` still draws all of it at 5 ms and `vfc` (1) would cost 2.7:
    // `hzb`'s frames bound `vfc`'s estimate from the boxes (45 ms), so it
    // is plausible, probed and chosen.
    let (frustum, draws) = boxes_until_a_cut(1e3);
    let cost = |i: usize, f: u64| if f < 60 { [50.0, 45.0, 30.0, 35.0][i] } else { [20.0, 2.7, 5.0, 6.0][i] };
    let mut c = chooser();
    let ds = decisions_in(&mut c, 100, 2, cost, draws, frustum, 1e6, |f| f == 60);
    assert!(share(&ds[20..60], 2) > 0.9, "{:?}", ds.iter().map(|d| d.candidate).collect::<Vec<_>>());
    assert!(share(&ds[80..], 1) > 0.9, "{:?}", ds.iter().map(|d| d.candidate).collect::<Vec<_>>());
}

#[test]
fn on_a_small_scene_noc_is_tried_once_the_frames_fit_the_cost_of_a_triangle() {
    // city300.glb's frame is its passes and pixels: `noc` (0) draws
    // 5,562 triangles, `vfc` (1) the 600-900 in the frustum, and `noc`
    // costs less (no culling pass). At the highest cost per triangle the
    // frames allow, `noc` would cost seven times `vfc`; the slope `vfc`'s
    // own frames fit (none) makes it plausible, and it is tried and kept.
    let frustum = |f: u64| 600.0 + 300.0 * ((f % 7) as f64 / 6.0);
    let draws = move |i: usize, f: u64| [5562.0, frustum(f), 0.3 * frustum(f), 0.2 * frustum(f)][i];
    let cost = |i: usize, _| [4.0, 4.4, 7.5, 8.0][i];
    let mut c = chooser();
    let ds = decisions_in(&mut c, 300, 2, cost, draws, frustum, 5562.0, |_| false);
    assert!(share(&ds[150..], 0) > 0.9, "{:?}", ds.iter().map(|d| d.candidate).collect::<Vec<_>>());
}

#[test]
fn at_an_isolated_cut_hzb_hands_over_to_hroc_whose_cold_frames_draw_less() {
    // hzb (2) 18 % cheaper than hroc (3) until a cut at frame 100; `vfc`
    // (1) three times hzb. hzb's frames from nothing draw the whole
    // frustum (35 ms, two of them); hroc's, reseeded, cost 15 and 12.
    let cost = |i: usize, f: u64| match (i, f) {
        (2, 100..=101) => 35.0,
        (3, 100) => 15.0,
        (3, 101) => 12.0,
        _ => [60.0, 30.0, 9.0, 11.0][i],
    };
    let draws = |i: usize, _| [1e6, 5e5, 6e4, 5e4][i];
    let at_cut = |cuts: &dyn Fn(u64) -> bool| {
        let mut c = chooser_as_auto();
        let ds = decisions_in(&mut c, 104, 2, cost, draws, |_| 5e5, 1e6, cuts);
        assert!(ds[96..100].iter().all(|d| d.candidate == 2), "{:?}", ds.iter().map(|d| d.candidate).collect::<Vec<_>>());
        ds[100]
    };
    // At the cut both start from nothing: hroc takes over, cold.
    let d = at_cut(&|f| f == 100);
    assert!(d.candidate == 3 && d.fresh && d.from.is_none(), "{d:?}");
    // Without a cut hzb stays.
    assert_eq!(at_cut(&|_| false).candidate, 2);
}

#[test]
fn a_spiky_frame_of_vfc_is_bounded_by_its_first() {
    // A small scene: vfc (1) cheapest at 4 ms, hzb (2) 7, hroc (3) 8;
    // vfc's one measured frame in the calibration spikes to 9 ms. Its
    // first frame ever (4 ms), a warm-up of vfc alone, bounds it: the
    // calibration ends on vfc or noc, not on hzb for thirty frames.
    let flat = |i: usize, _| [4.2, 4.0, 7.0, 8.0][i];
    let draws = |i: usize, _| [5600.0, 800.0, 300.0, 120.0][i];
    let vfc_frames: Vec<usize> =
        decisions_in(&mut chooser(), 12, 1, flat, draws, |_| 800.0, 5600.0, |_| false).iter().enumerate().filter(|(_, d)| d.candidate == 1).map(|(f, _)| f).collect();
    let spike = vfc_frames[1] as u64;
    let cost = |i: usize, f: u64| if i == 1 && f == spike { 9.0 } else { flat(i, f) };
    let ds = decisions_in(&mut chooser(), 40, 1, cost, draws, |_| 800.0, 5600.0, |_| false);
    let end = vfc_frames[0] + 3;
    assert!(ds[end..].iter().all(|d| d.candidate <= 1), "{:?}", ds.iter().map(|d| d.candidate).collect::<Vec<_>>());
}
