//! Lone contacts resolved at their touch event, without a cluster.
//!
//! When a touch (two free shots, or a free shot and the specimen) comes off the queue,
//! the lean path (binary.rs) resolves it from one contact step before the touch until the
//! shots part. The result stands if nothing else can have come near while it lasted:
//! * every other present shot within reach of the contact (its size plus twice the
//!   speed bound times the contact's span, plus the reach of shots resolved ahead) is
//!   free, was last resolved before the contact starts, has no touch of its own pending
//!   before the contact ends, and its free path keeps clear of the contact's actual
//!   paths (`Outcome::clear_of`);
//! * a pair stays clear of the specimen; the shots end inside the domain.
//!
//! Otherwise nothing is changed and the touch opens a cluster (mod.rs), which handles
//! every case. The cluster's gathering, copies, pair lists, verification and commit are
//! what a stream's contacts cost most; a lone contact pays for the lean path's steps and
//! one neighbour scan per shot.

use super::binary::{self, Body, Neighbour, Settings};
use super::{Engine, NONE};
use crate::Vec3;

impl Engine<'_> {
    /// Resolves the touch of free shots `who` (one shot: the specimen) predicted at
    /// `t_on` if it is lone (module docs); returns whether it did. Nothing changes if not.
    pub(super) fn lone_contact(&mut self, who: &[usize], t_on: f64) -> bool {
        let c = &self.phys.contacts;
        if !self.lean || c.friction.is_some() || c.wall.is_some() {
            return false;
        }
        if !who
            .iter()
            .all(|&i| self.shots[i].is_active() && !self.shots[i].on_specimen)
        {
            return false;
        }
        let tc = self.contact_time(who, t_on);
        let s = who
            .iter()
            .map(|&i| self.t_ref[i])
            .fold(t_on - tc / self.phys.contact_steps, f64::max);
        if s >= t_on {
            return false;
        }
        let body = |i: usize| {
            let (pos, vel) = self.state_at(i, s);
            let b = self.shots[i].body;
            Body {
                pos,
                vel,
                mass: b.mass,
                radius: b.radius,
            }
        };
        let set = Settings {
            tolerance: self.phys.tolerance,
            contact_steps: self.phys.contact_steps,
        };
        // Long enough for any lean contact (it gives up beyond three Hertz times).
        let e = (t_on + 4.0 * tc).min(self.end);
        let starts: Vec<Body> = who.iter().map(|&i| body(i)).collect();
        let o = match who {
            [_, _] => binary::resolve(
                &c.pair
                    .as_ref()
                    .expect("BUG: shot-shot touch without pair contact")
                    .law,
                &self.flight,
                &starts[0],
                &starts[1],
                None,
                s,
                e,
                s,
                set,
                &mut self.pair_dopri,
            ),
            _ => binary::resolve_specimen(
                &c.specimen
                    .as_ref()
                    .expect("BUG: floor touch without specimen")
                    .law,
                &self.flight,
                &starts[0],
                None,
                s,
                e,
                s,
                set,
                &mut self.pair_dopri,
            ),
        };
        let Some(o) = o else {
            return false;
        };
        if o.touching
            || !o.state[..o.n]
                .iter()
                .all(|(p, _)| self.phys.domain.contains(p))
        {
            return false;
        }
        // Everybody who can come near: shots move at most `vb`; a shot resolved ahead sits
        // in the grid where it was handed back, up to a cluster chunk away in time.
        let vb = self.v_bound().max(o.v_max2.sqrt());
        let span = o.end - s;
        let specimen = c.specimen.is_some() && o.n == 2;
        let mut found = std::mem::take(&mut self.buf);
        let mut lone = true;
        'shots: for (q, start) in starts.iter().enumerate() {
            if specimen && !o.above_plane(q, start.pos.z, start.radius, self.flight.g) {
                lone = false;
                break;
            }
            let (box_lo, box_hi) = o.path_box(q, self.flight.g, s, (start.pos, start.vel));
            let reach = start.radius + self.r_max + 2.0 * vb * span + vb * 4.0 * tc;
            found.clear();
            self.grid
                .for_each_within(&start.pos, reach, |k| found.push(k));
            for &k in &found {
                if who.contains(&k) || !self.present[k] {
                    continue;
                }
                // What is known of it: free from its clock until its next touch; a
                // shot of a cluster in progress only where its chunk ended; outside
                // that, within the speed bound.
                let (clock, owned) = (self.t_ref[k], self.owner[k] != NONE);
                let nc = self.next_change[k].without(who);
                let until = if owned {
                    clock
                } else if nc >= self.t_now {
                    nc
                } else {
                    f64::INFINITY
                };
                // Far from the box holding our path wherever it can be: clear.
                let t_mid = s.clamp(clock, until.max(clock));
                let centre = self
                    .flight
                    .at(&self.shots[k].pos, &self.shots[k].vel, t_mid - clock)
                    .0;
                let roam = vb * (o.end - t_mid).max(t_mid - s);
                let gap = (box_lo - centre)
                    .sup(&(centre - box_hi))
                    .sup(&Vec3::zeros())
                    .norm();
                if gap > start.radius + self.shots[k].body.radius + roam {
                    continue;
                }
                let nb = Neighbour {
                    clock,
                    pos: self.shots[k].pos,
                    vel: self.shots[k].vel,
                    until,
                    bounded_before: owned || clock > o.from,
                    speed: vb,
                    sigma: start.radius + self.shots[k].body.radius,
                };
                if !o.clear_of(q, &self.flight, s, (start.pos, start.vel), &nb) {
                    lone = false;
                    break 'shots;
                }
            }
        }
        self.buf = found;
        if !lone {
            return false;
        }
        // Hand the shots back, free from the moment they part.
        for (q, &m) in who.iter().enumerate() {
            o.apply(q, &mut self.shots[m], &mut self.out.impacts);
            self.t_ref[m] = o.end;
            self.ver[m] += 1;
            self.v_max = self.v_max.max(self.shots[m].vel.norm());
            let cell = self.grid.cell_of(&self.shots[m].pos);
            self.grid.place(m, cell);
        }
        o.count(&mut self.out.work);
        for &m in who {
            if self.t_ref[m] < self.end {
                self.predict(m);
            }
        }
        true
    }
}
