//! The default layout a run's recording opens with (the parent module's
//! doc describes it).

use std::collections::BTreeMap;

use super::logged::entity_part;
use crate::run::Twin;

/// The default layout of a run's recording (module doc).
pub fn blueprint(twin: &Twin) -> rerun::blueprint::Blueprint {
    use rerun::blueprint::components::PanelState;
    use rerun::blueprint::{
        Blueprint, ContainerLike, Horizontal, SelectionPanel, Spatial3DView, Tabs, TextLogView, TimePanel,
        TimeSeriesView, Vertical,
    };

    let (task, plant) = (twin.task(), twin.plant());
    let cell = Spatial3DView::new("Cell").with_origin("/").with_contents([
        "/robot/**",
        "/obstacles/**",
        "/tool_trails/**",
        "/collisions/contacts",
        "/conveyors/**",
        "/parts/**",
        "/cylinders/**",
        "/sensors/**",
    ]);

    // Axis groups: each coordinate system, then the axes in none.
    let name_of: BTreeMap<_, _> = plant.axes().iter().map(|a| (a.handle, a.name.as_str())).collect();
    let mut groups: Vec<(String, Vec<&str>)> = task
        .coord_handles()
        .map(|h| {
            let axes = task
                .coord_axes(h)
                .iter()
                .filter_map(|a| name_of.get(a).copied())
                .collect();
            (task.coord_config(h).name.clone(), axes)
        })
        .collect();
    let single: Vec<&str> = plant
        .axes()
        .iter()
        .filter(|a| !groups.iter().any(|(_, axes)| axes.contains(&a.name.as_str())))
        .map(|a| a.name.as_str())
        .collect();
    if !single.is_empty() {
        groups.push(("Axes".to_string(), single));
    }
    let series = |axes: &[&str], leaves: &[&str]| -> Vec<String> {
        axes.iter()
            .flat_map(|a| leaves.iter().map(move |l| format!("/axes/{}/{l}", entity_part(a))))
            .collect()
    };
    let group_views: Vec<ContainerLike> = groups
        .iter()
        .map(|(name, axes)| {
            let mut views: Vec<ContainerLike> = vec![
                TimeSeriesView::new(format!("{name} position"))
                    .with_contents(series(axes, &["cmd_pos", "act_pos"]))
                    .into(),
                TimeSeriesView::new(format!("{name} velocity"))
                    .with_contents(series(axes, &["cmd_vel", "act_vel"]))
                    .into(),
            ];
            let driven: Vec<&str> = axes
                .iter()
                .copied()
                .filter(|a| {
                    plant
                        .axes()
                        .iter()
                        .position(|b| b.name == *a)
                        .is_some_and(|k| plant.drive_torque(k).is_some())
                })
                .collect();
            if !driven.is_empty() {
                views.push(
                    TimeSeriesView::new(format!("{name} torque"))
                        .with_contents(series(&driven, &["torque"]))
                        .into(),
                );
            }
            Vertical::new(views).with_name(name.clone()).into()
        })
        .collect();

    let mut state: Vec<ContainerLike> = vec![
        TimeSeriesView::new("Program")
            .with_contents(["/instructions/**", "/tags/**"])
            .into(),
    ];
    let mut logs: Vec<ContainerLike> = vec![
        TextLogView::new("Instruction log")
            .with_origin("/instructions/log")
            .with_contents(["/instructions/log"])
            .into(),
    ];
    if !twin.scene().tasks.is_empty() {
        logs.push(
            TextLogView::new("Controller log")
                .with_origin("/controller/log")
                .with_contents(["/controller/log"])
                .into(),
        );
    }
    if twin.program().traced_tags().iter().any(|t| t.is_text()) {
        logs.push(
            TextLogView::new("Strings")
                .with_origin("/tags")
                .with_contents(["/tags/**"])
                .into(),
        );
    }
    if plant.collision_enabled() {
        state.push(
            TimeSeriesView::new("Clearance")
                .with_origin("/collisions/clearance")
                .into(),
        );
        logs.push(
            TextLogView::new("Collision log")
                .with_origin("/collisions/log")
                .with_contents(["/collisions/log"])
                .into(),
        );
    }
    let mut right: Vec<ContainerLike> = Vec::new();
    if !group_views.is_empty() {
        right.push(Tabs::new(group_views).into());
    }
    right.push(Tabs::new(state).into());
    let left = Vertical::new([cell.into(), Tabs::new(logs).into()]).with_row_shares([3.0, 1.0]);
    Blueprint::new(Horizontal::new([left.into(), Vertical::new(right).into()]))
        .with_time_panel(TimePanel::new().with_timeline(super::super::SIM_TIME_TIMELINE))
        .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
}
