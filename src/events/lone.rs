//! Lone contacts resolved at their touch event, without a cluster.
//!
//! When a touch (two free shots, or a free shot and the specimen) comes off the queue,
//! the lean path (binary.rs) resolves it from one contact step before the touch until the
//! shots part. The result stands if nothing else can have come near while it lasted:
//! * every other present shot within reach of the contact (its size plus twice the
//!   speed bound times the contact's span, plus the reach of shots resolved ahead) keeps
//!   clear of the contact's actual paths (`Outcome::clear_of`): on its free path while
//!   that is known, from its clock until its next pending touch or until a shot near it
//!   whose own path may change first could reach it (`Engine::chain_bound`, session
//!   62), and anywhere within the speed bound outside that (a shot of a cluster in
//!   progress is known only where its chunk ended);
//! * a pair stays clear of the specimen; the shots end inside the domain.
//!
//! Otherwise nothing is changed and the touch opens a cluster (mod.rs), which handles
//! every case. A cluster whose chunk ends with nothing held but one contact in progress
//! (two shots, or one on the specimen) is continued the same way, from the chunk's end
//! until the shots part, before another chunk is gathered (`lean_continuations`). The cluster's gathering, copies, pair lists, verification and commit are
//! what a stream's contacts cost most; a lone contact pays for the lean path's steps and
//! one neighbour scan per shot.

use super::binary::{Body, InProgress, Neighbour};
use super::{Cluster, Engine, NONE};
use crate::Vec3;

impl Engine<'_> {
    /// Resolves the touch of free shots `who` (one shot: the specimen) predicted at
    /// `t_on` if it is lone (module docs); returns whether it did. Nothing changes if not.
    pub(super) fn lone_contact(&mut self, who: &[usize], t_on: f64) -> bool {
        if !self.lone_applies(who) {
            return false;
        }
        let tc = self.contact_time(who, t_on);
        let s = who
            .iter()
            .map(|&i| self.fly[i].t_ref)
            .fold(t_on - tc / self.phys.contact_steps, f64::max);
        if s >= t_on {
            return false;
        }
        self.lone(who, s, (t_on + 4.0 * tc).min(self.end), None)
    }

    /// Continues cluster `cl` (taken out of its slot) if all it holds is one contact in
    /// progress between its shots (two shots, or one on the specimen) and that contact is
    /// lone until the shots part; returns whether it did (the cluster is then over and
    /// its shots fly free). Nothing changes if not.
    pub(super) fn lone_continuation(&mut self, cl: &Cluster) -> bool {
        let who = &cl.members[..];
        if !self.lone_applies(who) || who.iter().any(|&i| self.fly[i].t_ref != cl.clock) {
            return false;
        }
        let progress = match who {
            [a, b] => {
                let key = (self.shots[*a].id.0, self.shots[*b].id.0);
                let key = (key.0.min(key.1), key.0.max(key.1));
                match (cl.pairs.len(), cl.pairs.get(&key)) {
                    (1, Some(p)) if !self.shots[*a].on_specimen && !self.shots[*b].on_specimen => {
                        InProgress {
                            onset: p.onset,
                            contact_time: p.contact_time,
                            damping: f64::NAN,
                        }
                    }
                    _ => return false,
                }
            }
            [a] if cl.pairs.is_empty() && self.shots[*a].on_specimen => InProgress {
                onset: self.shots[*a].specimen_onset,
                contact_time: self.shots[*a].specimen_contact_time,
                damping: self.shots[*a].specimen_damping,
            },
            _ => return false,
        };
        let e = (progress.onset + 4.0 * progress.contact_time).min(self.end);
        let done = e > cl.clock && self.lone(who, cl.clock, e, Some(progress));
        self.out.work.lean_continuations += u64::from(done);
        done
    }

    /// Whether shots `who` can take the lean path at all.
    fn lone_applies(&self, who: &[usize]) -> bool {
        let c = &self.phys.contacts;
        self.lean
            && c.wall.is_none()
            && who
                .iter()
                .all(|&i| self.shots[i].is_active() && !self.shots[i].on_wall)
    }

    /// The lean path for shots `who` from `s` (their states there) until they part (at
    /// the latest `e`), fresh (`progress` `None`: the touch comes first) or a contact in
    /// progress; commits and returns `true` if nobody else can come near it (module docs).
    fn lone(&mut self, who: &[usize], s: f64, e: f64, progress: Option<InProgress>) -> bool {
        let c = &self.phys.contacts;
        if progress.is_none() && who.iter().any(|&i| self.shots[i].on_specimen) {
            return false;
        }
        let body = |i: usize| {
            let (pos, vel) = self.state_at(i, s);
            let b = self.shots[i].body;
            Body {
                pos,
                vel,
                omega: self.shots[i].omega,
                mass: b.mass,
                radius: b.radius,
            }
        };
        let starts: Vec<Body> = who.iter().map(|&i| body(i)).collect();
        let o = self.lean_outcome(&starts, progress, s, e, s);
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
            let reach = start.radius + self.r_max + 2.0 * vb * span + vb * 4.0 * o.contact_time;
            found.clear();
            self.grid
                .for_each_within(&start.pos, reach, |k| found.push(k));
            // The shots whose paths may change before the contact ends, found once
            // some neighbour's free path is relied on.
            let mut changers = std::mem::take(&mut self.changers);
            let mut changers_found = false;
            let mut clear = true;
            for &k in &found {
                if who.contains(&k) || !self.slot[k].present {
                    continue;
                }
                // What is known of it: free from its clock until its next touch (or
                // until a neighbour's change may reach it); a shot of a cluster in
                // progress only where its chunk ended; outside that, within the speed
                // bound.
                let (clock, owned) = (self.fly[k].t_ref, self.slot[k].owner != NONE);
                let t_now = self.t_now;
                let until_at = move |nc: f64| match (owned, nc >= t_now) {
                    (true, _) => clock,
                    (false, true) => nc,
                    (false, false) => f64::INFINITY,
                };
                // Far from the box holding our path wherever it can be: clear. (Its
                // pending touch, found afresh below if the kept one is past, is not needed
                // here: it is at least `t_now`, so the middle is the same.)
                let until = until_at(self.next_change[k].without(who));
                let t_mid = s.clamp(clock, until.max(clock));
                let centre = self
                    .flight
                    .at(&self.fly[k].pos, &self.fly[k].vel, t_mid - clock)
                    .0;
                let roam = vb * (o.end - t_mid).max(t_mid - s);
                let gap = (box_lo - centre)
                    .sup(&(centre - box_hi))
                    .sup(&Vec3::zeros())
                    .norm();
                if gap > start.radius + self.fly[k].radius + roam {
                    continue;
                }
                let mut until = until_at(self.pending(k).without(who));
                if !owned && until > clock {
                    if !changers_found {
                        self.changers_in(&found, who, u64::MAX, o.end, &mut changers);
                        changers_found = true;
                    }
                    until = self.chain_bound(k, &mut changers, who, until, vb, o.end);
                }
                let nb = Neighbour {
                    clock,
                    pos: self.fly[k].pos,
                    vel: self.fly[k].vel,
                    until,
                    bounded_before: owned || clock > o.from,
                    speed: vb,
                    sigma: start.radius + self.fly[k].radius,
                };
                if !o.clear_of(q, &self.flight, s, (start.pos, start.vel), &nb) {
                    clear = false;
                    break;
                }
            }
            self.changers = changers;
            if !clear {
                lone = false;
                break 'shots;
            }
        }
        self.buf = found;
        if !lone {
            return false;
        }
        // Hand the shots back, free from the moment they part.
        for (q, &m) in who.iter().enumerate() {
            o.apply(q, &mut self.shots[m], &mut self.out.impacts);
            self.sync(m);
            self.slot[m].owner = NONE;
            self.fly[m].t_ref = o.end;
            self.slot[m].ver += 1;
            self.v_max = self.v_max.max(self.shots[m].vel.norm());
            let cell = self.grid.cell_of(&self.shots[m].pos);
            self.grid.place(m, cell);
        }
        o.count(&mut self.out.work);
        for &m in who {
            if self.fly[m].t_ref < self.end {
                self.predict(m);
            }
        }
        true
    }
}
