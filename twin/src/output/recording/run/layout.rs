//! The default layout a run's recording opens with (the parent module's
//! doc describes it).

use std::collections::BTreeMap;

use super::paths::{entity_part, instruction_entity, program_of, tag_entity};
use crate::run::Twin;

/// The default layout of a run's recording (module doc).
pub fn blueprint(twin: &Twin) -> rerun::blueprint::Blueprint {
    use rerun::blueprint::components::PanelState;
    use rerun::blueprint::{
        Blueprint, ContainerLike, Horizontal, SelectionPanel, Spatial3DView, StateTimelineView, Tabs, TextDocumentView,
        TextLogView, TimePanel, TimeSeriesView, Vertical,
    };

    let (task, plant) = (twin.task(), twin.plant());
    let robot = format!("/{}/**", super::super::robot_entity_path(&plant.model().name));
    let cell = Spatial3DView::new("Cell").with_origin("/").with_contents([
        robot.as_str(),
        "/cameras/**",
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
                    .with_contents(series(axes, &["position"]))
                    .into(),
                TimeSeriesView::new(format!("{name} velocity"))
                    .with_contents(series(axes, &["velocity"]))
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

    // A tab per program: its instructions' and tags' state lanes, and its
    // routines; the controller's own (and a seed program's) first.
    let mut state: Vec<ContainerLike> = programs(twin)
        .into_iter()
        .map(|(name, lanes, routines)| {
            let lanes: ContainerLike = StateTimelineView::new(name.clone()).with_contents(lanes).into();
            if routines.is_empty() {
                lanes
            } else {
                let text = TextDocumentView::new(format!("{name} routines")).with_contents(routines);
                Vertical::new([lanes, text.into()])
                    .with_row_shares([1.0, 1.0])
                    .with_name(name)
                    .into()
            }
        })
        .collect();
    let mut logs: Vec<ContainerLike> = vec![
        TextLogView::new("Instruction log")
            .with_origin("/instructions/log")
            .with_contents(["/instructions/log"])
            .into(),
        TextLogView::new("Controller log")
            .with_origin("/controller/log")
            .with_contents(["/controller/log"])
            .into(),
    ];
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
                .with_contents(["/collisions/clearance"])
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
    if !state.is_empty() {
        right.push(Tabs::new(state).into());
    }
    let left = Vertical::new([cell.into(), Tabs::new(logs).into()]).with_row_shares([3.0, 1.0]);
    Blueprint::new(Horizontal::new([left.into(), Vertical::new(right).into()]))
        .with_time_panel(TimePanel::new().with_timeline(super::super::SIM_TIME_TIMELINE))
        .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
}

/// The program tabs: per program (in scene order; first `Controller`, for
/// the controller's tags and a seed program's instructions, when it has
/// any) its name, the entities of its instructions' and traced tags' state
/// lanes, and its routines' documents.
fn programs(twin: &Twin) -> Vec<(String, Vec<String>, Vec<String>)> {
    let scene = twin.scene();
    let program = twin.program();
    let names: Vec<&str> = scene
        .tasks
        .iter()
        .flat_map(|t| &t.programs)
        .map(|p| p.name.as_str())
        .collect();
    // `Program.Tag`: the program's; otherwise the controller's.
    let owner = |name: &str| -> Option<usize> {
        let program = program_of(twin, name)?;
        names.iter().position(|p| *p == program)
    };
    let mut tabs: Vec<(String, Vec<String>, Vec<String>)> = std::iter::once("Controller")
        .chain(names.iter().copied())
        .map(|n| (n.to_owned(), Vec::new(), Vec::new()))
        .collect();
    let instances = program
        .fbs()
        .iter()
        .map(|fb| fb.name.as_str())
        .chain(program.instructions().iter().map(|i| i.name.as_str()));
    for name in instances {
        let k = owner(name).map_or(0, |k| k + 1);
        tabs[k].1.push(format!("/{}", instruction_entity(name)));
    }
    for tag in program.traced_tags() {
        let path = format!("/{}", tag_entity(twin, tag));
        if tabs.iter().any(|t| t.1.contains(&path)) {
            continue;
        }
        let k = match &tag.entity {
            // A traced rung: `program/<program>/<routine>/<rung>`.
            Some(_) => path
                .split('/')
                .nth(2)
                .and_then(|p| names.iter().position(|n| entity_part(n) == p))
                .map_or(0, |k| k + 1),
            None => owner(&tag.name).map_or(0, |k| k + 1),
        };
        tabs[k].1.push(path);
    }
    for (k, name) in names.iter().enumerate() {
        tabs[k + 1].2.push(format!("/routines/{}/**", entity_part(name)));
    }
    tabs.retain(|(_, lanes, routines)| !lanes.is_empty() || !routines.is_empty());
    tabs
}
