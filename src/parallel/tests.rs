use super::*;

#[test]
fn every_part_runs_once_and_results_come_back_in_part_order() {
    let team = Team::new(2).unwrap();
    team.awake_for(|| {
        assert_eq!(team_size(), 2);
        // 0..1000 in blocks of 32: 32 parts, the first 16 this thread's own, the last 16 the
        // worker's.
        let ranges = team_blocks(1000).unwrap();
        assert_eq!(ranges.len(), 32);
        assert_eq!((ranges[0].clone(), ranges[31].clone()), (0..32, 992..1000));
        let runs = AtomicUsize::new(0);
        for _ in 0..200 {
            let who = on_team(ranges.clone(), |k, r| {
                runs.fetch_add(1, Ordering::SeqCst);
                (k, r.start)
            });
            for (k, (part, start)) in who.iter().enumerate() {
                assert_eq!((*part, *start), (k, 32 * k));
            }
        }
        assert_eq!(runs.load(Ordering::SeqCst), 200 * 32);
        // Disjoint mutable pieces: each element written once, by index.
        let mut data = vec![0usize; 1000];
        let ranges = team_blocks(data.len()).unwrap();
        let parts: Vec<_> = ranges
            .iter()
            .zip(split_ranges(&mut data, &ranges))
            .collect();
        on_team(parts, |_, (r, piece)| {
            for (x, i) in piece.iter_mut().zip(r.clone()) {
                *x = i;
            }
        });
        assert!(data.iter().enumerate().all(|(i, &x)| i == x));
    });
    // Outside `awake_for` the caller has no team: one part, run here.
    assert_eq!(team_size(), 1);
    assert_eq!(team_blocks(1000), None);
}

/// The worker takes parts when it keeps pace (dealt ones, or the caller's when the caller
/// is slow), and the caller takes the worker's when the worker is slow: the results are
/// the same whoever ran what.
#[test]
fn a_slow_member_s_parts_are_taken_by_the_other() {
    let team = Team::new(2).unwrap();
    let sum_of = |slow_name: Option<&str>| {
        team.awake_for(|| {
            let out = on_team((0..16).collect(), |k, x: u64| {
                if std::thread::current().name() == slow_name {
                    std::thread::sleep(Duration::from_millis(5));
                }
                (k, x * x, std::thread::current().name().map(str::to_owned))
            });
            let on_worker = out
                .iter()
                .filter(|o| o.2.as_deref() == Some("fractum-team-1"))
                .count();
            (out.iter().map(|o| o.1).collect::<Vec<_>>(), on_worker)
        })
    };
    let squares: Vec<u64> = (0..16).map(|x| x * x).collect();
    // The worker sleeps in each of its parts: the caller takes most of them.
    let (worker_slow, on_worker) = sum_of(Some("fractum-team-1"));
    assert_eq!(worker_slow, squares);
    assert!(on_worker < 8, "the worker ran {on_worker} of 16");
    let (caller_slow, _) = sum_of(std::thread::current().name());
    assert_eq!(caller_slow, squares);
}

/// Each member's own parts are a contiguous run, taken from its front; a member done with its
/// own takes the others' from their far end. With the caller slow, the worker runs its own
/// run 8..16 in order, then the caller's from 7 down.
#[test]
fn a_member_takes_its_own_run_from_the_front_and_the_others_from_the_back() {
    let team = Team::new(2).unwrap();
    let caller = std::thread::current().name().map(str::to_owned);
    let order = AtomicUsize::new(0);
    let ran = team.awake_for(|| {
        on_team((0..16).collect(), |k, _: usize| {
            let on_caller = std::thread::current().name().map(str::to_owned) == caller;
            if on_caller {
                std::thread::sleep(Duration::from_millis(5));
            }
            (order.fetch_add(1, Ordering::SeqCst), k, on_caller)
        })
    });
    let mut by_worker: Vec<_> = ran.iter().filter(|r| !r.2).map(|r| (r.0, r.1)).collect();
    by_worker.sort();
    let parts: Vec<usize> = by_worker.iter().map(|r| r.1).collect();
    assert!(parts.len() >= 8, "the worker ran {parts:?}");
    assert_eq!(
        parts[..8],
        [8, 9, 10, 11, 12, 13, 14, 15],
        "the worker ran {parts:?}"
    );
    assert!(
        parts[8..].windows(2).all(|w| w[0] > w[1]),
        "the worker ran {parts:?}"
    );
    assert!(ran[0].2, "part 0 is the caller's first");
}

#[test]
fn a_panic_in_a_part_reaches_the_caller_after_all_finish_and_the_team_goes_on() {
    let team = Team::new(2).unwrap();
    let finished = AtomicUsize::new(0);
    team.awake_for(|| {
        let caught = panic::catch_unwind(AssertUnwindSafe(|| {
            on_team((0..8).collect(), |k, _: usize| {
                if k == 3 {
                    panic!("part 3 fails");
                }
                std::thread::sleep(Duration::from_millis(2));
                finished.fetch_add(1, Ordering::SeqCst);
            })
        }));
        let msg = caught.expect_err("the part's panic is raised on the caller");
        assert_eq!(msg.downcast_ref::<&str>(), Some(&"part 3 fails"));
        // The other parts had finished before the panic was raised.
        assert_eq!(finished.load(Ordering::SeqCst), 7);
        assert_eq!(on_team(vec![1, 2, 3], |_, x| x + 1), vec![2, 3, 4]);
    });
}

/// A team awake with fewer members than it has deals its work to those only: the others
/// never run a part, and take part again once the whole team is awake.
#[test]
fn a_team_awake_with_fewer_members_leaves_the_others_out() {
    let team = Team::new(4).unwrap();
    let names = |members: Option<usize>| {
        let run = || {
            let size = team_size();
            let mut seen = std::collections::BTreeSet::new();
            for _ in 0..300 {
                let out = on_team((0..64).collect(), |k, x: usize| {
                    std::thread::sleep(Duration::from_micros(20));
                    (k, x, std::thread::current().name().map(str::to_owned))
                });
                assert!(out.iter().enumerate().all(|(k, o)| o.0 == k && o.1 == k));
                seen.extend(out.into_iter().filter_map(|o| o.2));
            }
            (size, seen)
        };
        match members {
            Some(m) => team.awake_with(m, run),
            None => team.awake_for(run),
        }
    };
    let (size, seen) = names(Some(2));
    assert_eq!(size, 2);
    assert!(
        seen.iter()
            .all(|n| !n.starts_with("fractum-team-") || n == "fractum-team-1"),
        "{seen:?}"
    );
    let (size, seen) = names(None);
    assert_eq!(size, 4);
    assert!(
        seen.contains("fractum-team-2") || seen.contains("fractum-team-3"),
        "{seen:?}"
    );
    assert_eq!(team_size(), 1);
}

#[test]
fn a_region_inside_a_job_runs_on_the_member_in_order() {
    let team = Team::new(2).unwrap();
    team.awake_for(|| {
        let inner = on_team(vec![0, 1], |_, k| {
            on_team(vec![10 * k, 10 * k + 1], |_, x| x)
        });
        assert_eq!(inner, vec![vec![0, 1], vec![10, 11]]);
    });
}

/// A job that claims its work: `count` units, each done once by whoever claims it.
fn claiming(count: usize, done: &AtomicUsize) -> impl Fn(usize) + Sync + '_ {
    let next = AtomicUsize::new(0);
    move |_| {
        while next.fetch_add(1, Ordering::SeqCst) < count {
            done.fetch_add(1, Ordering::SeqCst);
        }
    }
}

#[test]
fn two_callers_at_once_each_get_all_their_work_done() {
    let team = Team::new(2).unwrap();
    let total = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| {
                for _ in 0..2000 {
                    team.run(&claiming(3, &total));
                }
            });
        }
    });
    assert_eq!(total.load(Ordering::SeqCst), 2 * 2000 * 3);
}

#[test]
fn a_sleeping_team_completes_each_job() {
    let team = Team::new(2).unwrap();
    // Not awake: the worker sleeps between jobs, and each run still completes.
    for n in 0..50 {
        let done = AtomicUsize::new(0);
        team.run(&claiming(n + 1, &done));
        assert_eq!(done.load(Ordering::SeqCst), n + 1);
        if n % 10 == 0 {
            std::thread::sleep(Duration::from_millis(2));
        }
    }
}
