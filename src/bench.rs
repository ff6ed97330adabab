//! Timing runs: what every model's benchmark (`fractum bench`, `cargo bench`) measures of a
//! case, and the one table they print. Figures only: nothing here asserts a speed.

/// One timed case: `bodies` (particles, lattice elements or polygons) stepped `steps` times
/// in `seconds` of wall time on `threads` threads, with `contacts` contacts (or cohesive
/// contacts) at the end when the model counts them.
#[derive(Debug, Clone)]
pub struct Timed {
    /// What was run (a scene's name, or the sample's description).
    pub case: String,
    pub bodies: usize,
    pub contacts: Option<usize>,
    pub threads: usize,
    pub steps: u64,
    pub seconds: f64,
}

impl Timed {
    /// Body-steps per second of wall time.
    pub fn body_steps_per_second(&self) -> f64 {
        self.bodies as f64 * self.steps as f64 / self.seconds
    }
}

/// The cases as one Markdown table; `unit` names a body of the model ("particle",
/// "element", "polygon").
pub fn table(unit: &str, cases: &[Timed]) -> String {
    let mut s = format!(
        "| case | {unit}s | contacts | threads | steps | wall s | {unit}-steps/s |\n|---|---:|---:|---:|---:|---:|---:|\n"
    );
    for c in cases {
        let contacts = c.contacts.map_or("–".to_string(), |n| n.to_string());
        s.push_str(&format!(
            "| {} | {} | {contacts} | {} | {} | {:.3} | {:.3e} |\n",
            c.case,
            c.bodies,
            c.threads,
            c.steps,
            c.seconds,
            c.body_steps_per_second()
        ));
    }
    s
}
