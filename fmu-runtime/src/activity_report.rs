//! The activity table of a model's default experiment (the chapter's Table 3.3, for every
//! element): the model is run in Co-Simulation over its DefaultExperiment, at its step size and
//! default tolerance, and each element's activity (eq. 3.3) is read at the stop time, with its
//! share among the elements of its class and of all elements, and whether a threshold would
//! drop it. `build-fmus` puts the table in the FMU's documentation and prints it
//! (`build-fmus effects <model>`).

use crate::documentation::escape;
use crate::elements::{ElementInfo, Kind};
use crate::instance::Instance;
use crate::log::Logger;
use crate::model::Model;
use crate::description::real_text as number;

/// Shares below this (in % of their class's total) mark an element a reduced model could drop.
pub const DROP_BELOW_PERCENT: f64 = 1.0;

/// One element's activity at the end of the default experiment.
#[derive(Clone, Debug, PartialEq)]
pub struct ActivityRow {
    pub name: String,
    pub component: String,
    pub kind: Kind,
    pub what: &'static str,
    /// Integral of |power| over the experiment, J.
    pub activity_j: f64,
    /// Share among the storage (or dissipative) elements, %; None for a source.
    pub share_percent: Option<f64>,
    /// Share among all storage and dissipative elements, %; None for a source.
    pub share_of_all_percent: Option<f64>,
}

impl ActivityRow {
    /// Whether a reduced model would drop it: a storage or dissipative element with some
    /// activity, but less than [`DROP_BELOW_PERCENT`] of its class's.
    pub fn would_drop(&self) -> bool {
        self.activity_j > 0.0 && self.share_percent.is_some_and(|s| s < DROP_BELOW_PERCENT)
    }

    /// "drop" (see [`would_drop`](Self::would_drop)), "absent" (no activity: the default
    /// configuration leaves the element out), or nothing.
    pub fn mark(&self) -> &'static str {
        if self.would_drop() {
            "drop"
        } else if self.activity_j == 0.0 {
            "absent"
        } else {
            ""
        }
    }
}

/// Runs the default experiment and reads every element's activity at its end. Err: the run
/// failed (the message says where).
pub fn default_experiment<M: Model>() -> Result<Vec<ActivityRow>, String> {
    let (_, _, table) = crate::model::declare::<M>();
    if table.elements.iter().all(|e| e.activity_state.is_none()) {
        return Ok(Vec::new());
    }
    let e = M::info().default_experiment;
    let mut inst = Instance::<M>::new("{activity-report}", Logger::silent());
    let fail = |what: &str, f: crate::instance::Failure| format!("{what}: {}", f.message);
    inst.setup_experiment(None, e.start_time, Some(e.stop_time)).map_err(|f| fail("setup", f))?;
    inst.enter_initialization_mode().map_err(|f| fail("initialization", f))?;
    inst.exit_initialization_mode().map_err(|f| fail("initialization", f))?;
    let steps = ((e.stop_time - e.start_time) / e.step_size).round() as u64;
    for n in 0..steps {
        let t = e.start_time + n as f64 * e.step_size;
        let h = if n + 1 == steps { e.stop_time - t } else { e.step_size };
        inst.do_step(t, h).map_err(|f| fail(&format!("doStep at t = {t} s"), f))?;
    }
    let activity_vr = |el: &ElementInfo| table.by_name(&format!("A_{}", el.name)).map(|v| v.value_reference);
    let mut activities = Vec::new();
    for el in table.elements.iter().filter(|el| el.activity_state.is_some()) {
        let vr = activity_vr(el).ok_or_else(|| format!("no state A_{}", el.name))?;
        let mut a = [0.0];
        inst.get(&[vr], &mut a).map_err(|f| fail("reading the activities", f))?;
        activities.push((el, a[0]));
    }
    let total = |storage: Option<bool>| -> f64 {
        activities
            .iter()
            .filter(|(el, _)| el.effect.kind != Kind::Source && storage.is_none_or(|s| el.effect.kind.is_storage() == s))
            .map(|(_, a)| a)
            .sum()
    };
    let (storage, dissipation, all) = (total(Some(true)), total(Some(false)), total(None));
    let percent = |a: f64, of: f64| if of > 0.0 { 100.0 * a / of } else { 0.0 };
    Ok(activities
        .into_iter()
        .map(|(el, a)| {
            let source = el.effect.kind == Kind::Source;
            let class = if el.effect.kind.is_storage() { storage } else { dissipation };
            ActivityRow {
                name: el.name.clone(),
                component: el.component.clone(),
                kind: el.effect.kind,
                what: el.effect.what,
                activity_j: a,
                share_percent: (!source).then(|| percent(a, class)),
                share_of_all_percent: (!source).then(|| percent(a, all)),
            }
        })
        .collect())
}

fn share_text(s: Option<f64>) -> String {
    s.map_or_else(|| "-".to_string(), |s| format!("{s:.3}"))
}

/// The activity table as (HTML, text), and Table 3.1 before it in the text; a failed run is
/// said in both.
pub fn report<M: Model>() -> (String, String) {
    let (_, _, table) = crate::model::declare::<M>();
    if table.elements.is_empty() {
        return (String::new(), String::new());
    }
    let effects = crate::elements::effects_table_text(&table.elements);
    match default_experiment::<M>() {
        Ok(rows) => (html::<M>(&rows), format!("Table 3.1, systematic analysis of effects:\n{effects}\nActivities over the default experiment:\n{}", text(&rows))),
        Err(e) => {
            let message = format!("the default experiment failed ({e}): no activity table");
            (format!("<p>{}</p>\n", escape(&message)), format!("{effects}\n{message}\n"))
        }
    }
}

/// The table as HTML for documentation/index.html, with the experiment it comes from.
pub fn html<M: Model>(rows: &[ActivityRow]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let e = M::info().default_experiment;
    let mut s = format!(
        "<h3>Activity of each element over the default experiment (the chapter's Table 3.3)</h3>\n<p>Co-Simulation from {} s to {} s, \
         communication step {} s, default tolerance, every parameter at its default; activity = integral of |power| dt (eq. 3.3). \
         Share: among the storage elements, or among the dissipative ones; of all: among both. Marked drop: below {} % of its class, an \
         element a reduced model could drop; absent: no activity, the default configuration leaves it out.</p>\n<table>\n<tr><th>element</th><th>component</th><th>effect</th><th>activity (J)</th>\
         <th>share (%)</th><th>of all (%)</th><th>below {} %</th></tr>\n",
        number(e.start_time),
        number(e.stop_time),
        number(e.step_size),
        DROP_BELOW_PERCENT,
        DROP_BELOW_PERCENT
    );
    for r in rows {
        s += &format!(
            "<tr><td><code>{}</code></td><td>{}</td><td>{}: {}</td><td>{:.6e}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape(&r.name),
            escape(&r.component),
            escape(r.what),
            r.kind.as_str(),
            r.activity_j,
            share_text(r.share_percent),
            share_text(r.share_of_all_percent),
            r.mark()
        );
    }
    s + "</table>\n"
}

/// The table as plain text (`build-fmus effects <model>`).
pub fn text(rows: &[ActivityRow]) -> String {
    let mut s = format!("{:<34} {:<22} {:<16} {:>14} {:>10} {:>10}  below {} %\n", "element", "component", "kind", "activity (J)", "share %", "of all %", DROP_BELOW_PERCENT);
    for r in rows {
        s += &format!(
            "{:<34} {:<22} {:<16} {:>14.6e} {:>10} {:>10}  {}\n",
            r.name,
            r.component,
            r.kind.as_str(),
            r.activity_j,
            share_text(r.share_percent),
            share_text(r.share_of_all_percent),
            r.mark()
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_oscillator_s_activities_come_from_its_default_experiment() {
        let rows = default_experiment::<crate::elements::tests::Oscillator<false, false>>().unwrap();
        let names: Vec<&str> = rows.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["force", "mass", "spring", "damper"]);
        let share = |n: &str| rows.iter().find(|r| r.name == n).unwrap().share_percent;
        assert_eq!(share("force"), None);
        assert!((share("mass").unwrap() + share("spring").unwrap() - 100.0).abs() < 1e-9);
        assert_eq!(share("damper"), Some(100.0));
        // The damper's activity is the energy it dissipated: 0.8 v^2 integrated, > 0.
        assert!(rows.iter().all(|r| r.activity_j > 0.0), "{rows:?}");
        let t = text(&rows);
        assert!(t.contains("damper") && t.contains("dissipation (R)"), "{t}");
        assert!(html::<crate::elements::tests::Oscillator<false, false>>(&rows).contains("<code>spring</code>"));
    }
}
