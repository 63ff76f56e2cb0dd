//! documentation/index.html: the model's own text (equations, sources of its values), then
//! generated tables of every variable, the default experiment, the solver and how to run it.

use crate::description::{real_text, Document, ModelDescription};
use crate::integrate::{declared_tolerance, ABSOLUTE_PER_RELATIVE, MAX_INTERNAL_STEPS};
use crate::model::Model;
use crate::variables::{Causality, Start, Variable};

/// Escapes text for HTML.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn start_text(v: &Variable) -> String {
    match v.start {
        Some(Start::Real(x)) => real_text(x),
        Some(Start::Integer(n)) => n.to_string(),
        Some(Start::Boolean(b)) => b.to_string(),
        None => "computed".into(),
    }
}

/// A declared minimum; a strictly positive quantity's (the smallest positive normal double) says so.
fn min_text(min: f64) -> String {
    if min == crate::variables::SMALLEST_POSITIVE {
        format!("{} (&gt; 0)", real_text(min))
    } else {
        real_text(min)
    }
}

/// An enumerated variable's items ("; items: 1 = a (quasi-static), 2 = b ..."), none for others.
fn items_text(v: &Variable) -> String {
    if v.items.is_empty() {
        return String::new();
    }
    let first = v.min.unwrap_or(1.0) as i32;
    let items: Vec<String> = v
        .items
        .iter()
        .enumerate()
        .map(|(k, (name, description))| format!("{} = <code>{}</code> ({})", first + k as i32, escape(name), escape(description)))
        .collect();
    format!("; Enumeration items: {}", items.join(", "))
}

fn table(title: &str, vars: &[&Variable]) -> String {
    if vars.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "<h3>{}</h3>\n<table>\n<tr><th>name</th><th>value reference</th><th>unit</th><th>start</th><th>min</th><th>max</th><th>variability</th><th>description</th></tr>\n",
        escape(title)
    );
    for v in vars {
        s += &format!(
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape(&v.name),
            v.value_reference,
            escape(v.unit.as_deref().unwrap_or("")),
            start_text(v),
            v.min.map(min_text).unwrap_or_default(),
            v.max.map(real_text).unwrap_or_default(),
            v.variability.as_str(),
            escape(&v.description) + &items_text(v)
        );
    }
    s + "</table>\n"
}

/// " Model version 0.1.0, Copyright (c) 2026 ..., license MIT, source of 2026-12-01T21:46:29Z.", as known.
fn package_text(p: &crate::description::Package) -> String {
    let mut parts = Vec::new();
    if !p.version.is_empty() {
        parts.push(format!("model version {}", escape(p.version)));
    }
    if let Some(c) = p.copyright() {
        parts.push(escape(&c));
    }
    if !p.license.is_empty() {
        parts.push(format!("license {}", escape(p.license)));
    }
    if let Some(date) = p.generation_date_and_time() {
        parts.push(format!("source of {date}"));
    }
    if parts.is_empty() {
        return String::new();
    }
    let mut text = parts.join(", ");
    text[..1].make_ascii_uppercase();
    format!(" {text}.")
}

/// Where `build-fmus` puts the activity table of the default experiment (it runs the model to
/// make it, `fmu_runtime_effects_html`).
pub const ACTIVITY_TABLE_MARK: &str = "<!-- activity table of the default experiment -->\n";

/// The elements of the model (Table 3.1) and what the runtime derives from them.
fn effects_section(elements: &[crate::elements::ElementInfo]) -> String {
    if elements.is_empty() {
        return String::new();
    }
    format!(
        "<h2>Effects, activity and energy balance</h2>\n{}<p>For every source, storage and dissipative element the FMU integrates its \
         activity, the integral of |power| dt (the chapter's eq. 3.3), under the solver's error control: the state <code>A_&lt;element&gt;</code> \
         and the output <code>activity_&lt;element&gt;</code>, in J; <code>share_&lt;element&gt;</code> is a storage element's share of the \
         storage elements' total activity (Table 3.3 ranks these), or a dissipative element's share of the dissipative elements' total, in %. \
         <code>power_balance_residual</code> is the sum of the source powers minus the rates of stored energy minus the dissipated powers, in W \
         (transformers are lossless; a thermal resistance passes its heat on), and <code>power_balance_relative</code> that residual over the \
         largest element power: 0 up to rounding while the equations conserve energy.</p>\n{}",
        crate::elements::effects_table_html(elements),
        ACTIVITY_TABLE_MARK
    )
}

/// What the documentation page says differently for each standard: its version, what it calls
/// the token, and the functions a user reads about.
pub struct Words {
    pub version: &'static str,
    /// FMI 2.0 `guid`, FMI 3.0 `instantiationToken`.
    pub token_name: &'static str,
    pub error: &'static str,
    pub discard: &'static str,
    pub do_step: &'static str,
    /// Where the master gives the tolerance.
    pub setup: &'static str,
    /// Where the master gives input derivatives, if the standard has such a function.
    pub input_derivatives: Option<&'static str>,
    pub new_discrete_states: &'static str,
    pub event_indicators: &'static str,
}

/// The documentation page of a model, for one standard's FMU.
pub fn html<M: Model>(d: &ModelDescription, document: &Document, w: &Words) -> String {
    let info = M::info();
    let vars = &d.table.variables;
    let of = |c: Causality| vars.iter().filter(|v| v.causality == c).collect::<Vec<_>>();
    let states: Vec<&Variable> = d.table.state_value_reference.iter().map(|vr| &vars[*vr as usize]).collect();
    let locals: Vec<&Variable> = vars
        .iter()
        .filter(|v| v.causality == Causality::Local && v.derivative_of.is_none() && d.table.state_index(v).is_none())
        .collect();
    let solver = crate::stepper::description(info.solver);
    let e = info.default_experiment;
    format!(
        r#"<!DOCTYPE html>
<html lang="en">
<head><meta charset="utf-8"><title>{name}</title>
<style>body{{font-family:sans-serif;max-width:60em;margin:2em auto;line-height:1.4}}table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:0.2em 0.5em;text-align:left}}code{{background:#f4f4f4}}</style>
</head>
<body>
<h1>{name}</h1>
<p>{description}</p>
<p>FMI {fmi_version} FMU for Co-Simulation and Model Exchange (one binary), {token_name} <code>{guid}</code>, generated by fmu-runtime {version}.{package}</p>
<h2>Model</h2>
{documentation}
{effects}<h2>Variables</h2>
<p>Every physical value is a parameter with its SI unit: set it before initialization to sweep or calibrate
without rebuilding. Values outside [min, max] (inclusive, as declared in modelDescription.xml) are refused with {error} and a message naming the parameter;
a strictly positive quantity declares the smallest positive double as its min.</p>
{parameters}{inputs}{outputs}{states}{locals}
<h2>Simulation</h2>
<p>Default experiment: {start} s to {stop} s, communication step {step} s.</p>
<p>Each <code>{do_step}</code> integrates with an adaptive {solver} with error control: relative tolerance from
<code>{setup}</code>, else {rtol} (the DefaultExperiment's tolerance){floor}; absolute tolerance of each state {atol_factor} &times; rtol &times; its nominal value.
Inputs are held over a communication step, unless {input_derivatives}the model's <code>extrapolate_inputs</code> parameter (where it has inputs) is on: each input then follows the
line through its last two values. While nothing changes between communication steps, the explicit solver
steps past the communication point with its own step size (never past a time event or a defined stop time) and interpolates
the state there, so a short communication step costs little. A step that would need more than {max_steps} internal steps, or whose
solution stops being finite, is refused with <code>{discard}</code> and the instance stays at the last communication point.</p>
<p>Events: the model's non-smooth instants (a ramp's end) are time events and its switching physics (where it has any)
event indicators with discrete modes; in Co-Simulation <code>{do_step}</code> stops the solver at each, updates the modes and
restarts. Model Exchange: the master's own solver integrates the same equations; time events are announced through
<code>{new_discrete_states}</code>, state events through <code>{event_indicators}</code>.</p>
<p>Capabilities: variable communication step size, get/set and serialize the FMU state, directional
derivatives (central differences of the equations, 1e-7 relative step, about 1e-9 relative on smooth equations), {input_derivative_capability}output
derivatives (order 1).</p>
<h2>Run it</h2>
<pre>import fmpy
result = fmpy.simulate_fmu("{name}.fmu", stop_time={stop}, output_interval={step})
</pre>
</body>
</html>
"#,
        name = escape(info.name),
        description = escape(info.description),
        guid = escape(&document.token),
        fmi_version = w.version,
        token_name = w.token_name,
        error = w.error,
        discard = w.discard,
        do_step = w.do_step,
        setup = w.setup,
        input_derivatives = w.input_derivatives.map_or(String::new(), |f| format!("the master gives their derivatives (<code>{f}</code>,\norders 1 and 2) or ")),
        input_derivative_capability = if w.input_derivatives.is_some() { "input derivatives (orders 1 and 2), " } else { "" },
        new_discrete_states = w.new_discrete_states,
        event_indicators = w.event_indicators,
        version = env!("CARGO_PKG_VERSION"),
        package = package_text(&d.package),
        documentation = info.documentation,
        effects = effects_section(&d.table.elements),
        parameters = table("Parameters", &of(Causality::Parameter)),
        inputs = table("Inputs", &of(Causality::Input)),
        outputs = table("Outputs", &of(Causality::Output)),
        states = table("Continuous states (initial values settable before initialization)", &states),
        locals = table("Other variables", &[locals, of(Causality::CalculatedParameter)].concat()),
        start = real_text(e.start_time),
        stop = real_text(e.stop_time),
        step = real_text(e.step_size),
        rtol = real_text(declared_tolerance(d.default_floor)),
        floor = d.default_floor.map_or(String::new(), |f| format!(
            ", tightened to this model's floor {} at its default parameters where it is looser (a warning through the logger names \
             both; the model's notes say where other parameters change it): at looser tolerances this model's errors grow far \
             beyond the tolerance, see the accuracy table in the project's README",
            real_text(f)
        )),
        atol_factor = real_text(ABSOLUTE_PER_RELATIVE),
        max_steps = MAX_INTERNAL_STEPS,
    )
}
