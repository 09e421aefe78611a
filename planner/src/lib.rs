//! Motion planner.
