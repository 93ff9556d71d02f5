//! Lone shots asleep across windows (the windows scheduler, adaptive method).
//!
//! In a nozzle stream most shots in flight are, in most windows, lone shots riding a
//! kept step (`ShotState::ahead`) that runs many windows past the window's end (session
//! 37's count on `bench/scenes/stream_10k.toml`: 6.6 M of 7.9 M shot-windows, with 14
//! windows left on the step on average). Every window still paid for each of them: its
//! acceleration bound and reach, the pair tests, an island, the state read off the step,
//! the verification and the commit. A sleeper skips all of that until its sleep ends;
//! only the window's broad phase sees it, as a ball.
//!
//! The ball holds, for every window the shot sleeps through, the reach ball it would
//! have had there ([`super::inflated_radius`] at its state at the window's start): the
//! step's chord over the sleep, on which its centre moves, widened by how far the step's
//! positions depart from the chord ([`DenseStep::bend`]) and by the reach the window's
//! length gives at the step's largest speed over the sleep.
//! So when no other shot's reach ball (and no other sleeper's ball) meets it, the
//! sleeper has no pair within absolute reach: in the run without sleepers it would be an
//! island of its own, not kicked, its state read off the same step, and its absence
//! changes no other shot's pairs, flags or islands. A window wakes the sleepers whose
//! ball meets anything or whose sleep ends in it. A lone shot that had a pair in the window's broad phase does not fall asleep
//! (it would wake at once: session 37 measured 2 M sleeps, most woken at the next
//! window, against 0.5 M). When a shot went beyond its reach, the window's overlap
//! search reads the sleepers' positions off their steps too; should a sleeper be in a
//! missed pair, all wake and the window runs again. The window length reads a
//! sleeper's speed off its step when the sleeper could be the fastest. Outputs are
//! those of the run without sleepers, byte for byte (tests/sleepers.rs).

use crate::Vec3;
use crate::integrate::dopri::DenseStep;
use crate::integrate::island::{Kept, Physics};
use crate::state::ShotState;

/// A lone shot asleep: its kept step covers `since..until`.
#[derive(Debug, Clone)]
pub(super) struct Sleeper {
    /// The shot's id.
    pub id: usize,
    /// When it fell asleep (its state is stored at that time).
    since: f64,
    /// It sleeps through windows that end before this (at most its kept step's end).
    until: f64,
    /// Its position at `since`, and the velocity of its step's chord over the sleep:
    /// the ball at `t` is centred on `start + chord (t - since)`.
    start: Vec3,
    chord: Vec3,
    /// The ball's radius less the reach's motion terms (see [`Self::radius`]).
    base: f64,
    /// Upper bounds of its speed while asleep, and of its body-force acceleration at
    /// 1.5 times that speed ([`super::body_acc`]).
    speed: f64,
    acc: f64,
    /// Its diameter.
    pub diameter: f64,
}

impl Sleeper {
    /// Puts lone shot `s`, whose state is stored at `t`, to sleep after a window `h`
    /// long, if its kept step runs at least one such window further.
    pub fn new(phys: &Physics, s: &ShotState, t: f64, h: f64) -> Option<Self> {
        let step = s.ahead.as_ref()?;
        let until = step.end();
        if until <= t + h || t < step.t0 {
            return None;
        }
        let (a, b) = (read(step, t), read(step, until));
        // How far the positions and the velocities depart from their chords.
        let (path, bend) = (step.bend(t, until, 0), step.bend(t, until, 3));
        let vec = |y: &[f64; 9], k: usize| Vec3::new(y[k], y[k + 1], y[k + 2]);
        // The stored state is the step's output at `t`, up to rounding; counted anyway.
        let stored = (s.pos - vec(&a, 0)).norm();
        let speed = vec(&a, 3).norm().max(vec(&b, 3).norm()).max(s.vel.norm()) + bend;
        Some(Sleeper {
            id: s.id.0 as usize,
            since: t,
            until,
            start: vec(&a, 0),
            chord: (vec(&b, 0) - vec(&a, 0)) / (until - t),
            // The reach's own 1e-9, and as much again for rounding.
            base: path + stored + s.body.radius + 2e-9,
            speed,
            acc: phys.forces.acceleration_bound(&s.body, 1.5 * speed + 1.0),
            diameter: 2.0 * s.body.radius,
        })
    }

    /// Whether a window ending at `t1` must wake it: its sleep ends there.
    pub fn due(&self, t1: f64) -> bool {
        t1 >= self.until
    }

    /// Its ball's radius in a window `h` long: the reach ([`super::inflated_radius`])
    /// at its speed bound, widened by the step's departure from its chord.
    #[inline]
    pub fn radius(&self, h: f64) -> f64 {
        self.base + 1.5 * self.speed * h + 0.5 * self.acc * h * h
    }

    /// Its ball's centre at `t`.
    #[inline]
    pub fn centre(&self, t: f64) -> Vec3 {
        self.start + self.chord * (t - self.since)
    }

    /// Its speed bound while asleep.
    pub fn speed_bound(&self) -> f64 {
        self.speed
    }

    /// Its speed at `t` (a time it sleeps through, or `since`), as its state would hold it.
    pub fn speed_at(&self, phys: &Physics, s: &ShotState, t: f64) -> f64 {
        if t > self.since {
            let kept = Kept::read(phys, s, t).expect("BUG: a sleeper's step covers its sleep");
            let y = kept.state();
            Vec3::new(y[3], y[4], y[5]).norm()
        } else {
            s.vel.norm()
        }
    }

    /// Its position at `t` (a time it sleeps through, or `since`), as its state would
    /// hold it.
    pub fn pos_at(&self, phys: &Physics, s: &ShotState, t: f64) -> Vec3 {
        if t > self.since {
            Kept::read(phys, s, t)
                .expect("BUG: a sleeper's step covers its sleep")
                .pos()
        } else {
            s.pos
        }
    }

    /// Wakes it at `t`: its state is read off its step there.
    pub fn wake(&self, phys: &Physics, s: &mut ShotState, t: f64) {
        if t > self.since {
            Kept::read(phys, s, t)
                .expect("BUG: a sleeper's step covers its sleep")
                .store(s);
        }
    }
}

/// The step's output at `t` (positions, velocities, then spin if any).
fn read(step: &DenseStep, t: f64) -> [f64; 9] {
    let mut y = [0.0; 9];
    let n = step.len();
    step.at(t, &mut y[..n]);
    y
}

/// The sleepers, by ascending id.
#[derive(Debug, Default)]
pub(super) struct Sleepers {
    list: Vec<Sleeper>,
}

impl Sleepers {
    /// How many sleep.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// Whether none sleeps.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The sleepers, ascending by id.
    pub fn iter(&self) -> impl Iterator<Item = &Sleeper> {
        self.list.iter()
    }

    /// Shot `id` if it sleeps (`cursor` walks the list for ascending queries).
    #[inline]
    pub fn find(&self, id: usize, cursor: &mut usize) -> Option<&Sleeper> {
        while self.list.get(*cursor).is_some_and(|s| s.id < id) {
            *cursor += 1;
        }
        self.list.get(*cursor).filter(|s| s.id == id)
    }

    /// Takes out the sleepers `wake` picks, ascending by id.
    pub fn take(&mut self, mut wake: impl FnMut(&Sleeper) -> bool) -> Vec<Sleeper> {
        let mut woken = Vec::new();
        self.list.retain(|s| {
            let w = wake(s);
            if w {
                woken.push(s.clone());
            }
            !w
        });
        woken
    }

    /// Adds sleepers (any order).
    pub fn extend(&mut self, mut new: Vec<Sleeper>) {
        if new.is_empty() {
            return;
        }
        new.sort_unstable_by_key(|s| s.id);
        let old = std::mem::take(&mut self.list);
        self.list.reserve(old.len() + new.len());
        let (mut a, mut b) = (old.into_iter().peekable(), new.into_iter().peekable());
        loop {
            let next = match (a.peek(), b.peek()) {
                (Some(x), Some(y)) if x.id < y.id => a.next(),
                (Some(_), Some(_)) => b.next(),
                (Some(_), None) => a.next(),
                (None, Some(_)) => b.next(),
                (None, None) => break,
            };
            self.list.extend(next);
        }
    }
}
