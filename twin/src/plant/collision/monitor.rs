//! Collision events over a run: the contacts of successive checks (and
//! the continuous detection's touches between them) turned into events
//! with a start, an end and their deepest contact.

use std::collections::BTreeMap;

use serde::Serialize;

use super::CollisionModel;
use super::bodies::{Body, CheckResult, Contact, ContactPoint};

/// A collision event: one pair in contact over a time interval.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CollisionEvent {
    /// Time of the first check with contact, s.
    pub start_s: f64,
    /// Time of the first check without contact afterwards, s (`None`: still in contact at the end).
    pub end_s: Option<f64>,
    /// First body (a robot body).
    pub a: String,
    /// Second body (an obstacle or robot body).
    pub b: String,
    /// The deepest contact seen.
    #[serde(flatten)]
    pub deepest: ContactPoint,
}

/// Tracks contacts over checks and turns them into events.
#[derive(Debug, Clone, Default)]
pub struct Monitor {
    open: BTreeMap<(Body, Body), usize>,
    events: Vec<CollisionEvent>,
}

impl Monitor {
    /// Takes in one check at `time_s`; returns the indices of the events
    /// that started at this check.
    pub fn observe(&mut self, model: &CollisionModel, time_s: f64, result: &CheckResult) -> Vec<usize> {
        self.observe_from(model, time_s, result, &[])
    }

    /// [`Monitor::observe`] with the continuous detection's first touches
    /// (`(τ time, contact)`, from [`CollisionModel::first_touches`] over the
    /// step that ends at `time_s`): an event that starts at this check
    /// starts at its pair's first touch; a pair that touched during the
    /// step but no longer does at its end is an event that opened and
    /// closed within the step (`end_s` = `time_s`, depth 0).
    pub fn observe_from(
        &mut self,
        model: &CollisionModel,
        time_s: f64,
        result: &CheckResult,
        touches: &[(f64, Contact)],
    ) -> Vec<usize> {
        let first = |a: Body, b: Body| touches.iter().find(|(_, c)| c.a == a && c.b == b).map(|(t, _)| *t);
        let event = |c: &Contact, start_s: f64, end_s: Option<f64>| CollisionEvent {
            start_s: start_s.min(time_s),
            end_s,
            a: model.name(c.a).to_string(),
            b: model.name(c.b).to_string(),
            deepest: c.at,
        };
        // Events that start at this check, with the key of those still open.
        let mut fresh: Vec<(Option<(Body, Body)>, CollisionEvent)> = Vec::new();
        let seen = |key: &(Body, Body)| result.contacts.iter().any(|c| (c.a, c.b) == *key);
        for c in &result.contacts {
            let key = (c.a, c.b);
            match self.open.get(&key) {
                Some(&i) => {
                    let e = &mut self.events[i];
                    if c.at.depth_m > e.deepest.depth_m {
                        e.deepest = c.at;
                    }
                }
                None => fresh.push((Some(key), event(c, first(c.a, c.b).unwrap_or(time_s), None))),
            }
        }
        let ended: Vec<(Body, Body)> = self.open.keys().filter(|k| !seen(k)).copied().collect();
        for key in ended {
            if let Some(i) = self.open.remove(&key) {
                self.events[i].end_s = Some(time_s);
            }
        }
        // Touched and let go within the step (the contact has depth 0).
        for (t, c) in touches {
            let key = (c.a, c.b);
            if !seen(&key) && !self.open.contains_key(&key) {
                fresh.push((None, event(c, *t, Some(time_s))));
            }
        }
        // In start order (a stable sort: ties stay in pair order).
        fresh.sort_by(|x, y| x.1.start_s.total_cmp(&y.1.start_s));
        let mut started = Vec::with_capacity(fresh.len());
        for (key, e) in fresh {
            if let Some(key) = key {
                self.open.insert(key, self.events.len());
            }
            started.push(self.events.len());
            self.events.push(e);
        }
        started
    }

    /// Every event so far, in start order (ties in pair order).
    pub fn events(&self) -> &[CollisionEvent] {
        &self.events
    }

    /// Robot bodies in an open event now.
    pub fn colliding(&self) -> Vec<Body> {
        let mut v: Vec<Body> = self.open.keys().flat_map(|(a, b)| [*a, *b]).collect();
        v.sort();
        v.dedup();
        v
    }
}
