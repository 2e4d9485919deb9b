//! Options set by name at run time: `newton.max_iter=20`, `policy.max_halvings=0`,
//! `tuning.far_correction=8`. The name is the option's path in the serialized
//! [`Options`]; the value is JSON (a number, `true`/`false`, a list) or else a string.
//! This is how the reference workload measures one constant's or one stage's effect
//! with one binary (`scripts/reference_workload.py BIN --variant NAME=VALUE`).

use crate::error::StepError;
use crate::options::Options;
use serde_json::Value;

impl Options {
    /// Sets the option `NAME` of the assignment `NAME=VALUE`, then checks the whole.
    ///
    /// ```
    /// let mut o = nsga::Options::default();
    /// o.set("tuning.stall_iterations=4").unwrap();
    /// o.set("policy.rho_inf_retries=[]").unwrap();
    /// assert_eq!(o.tuning.stall_iterations, 4);
    /// assert!(o.policy.rho_inf_retries.is_empty());
    /// let e = o.set("tuning.stall_iteration=4").unwrap_err().to_string();
    /// assert!(e.contains("stall_iterations"), "{e}");
    /// ```
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] naming the assignment: no `=`, a name that is no
    /// option (with the names there are at that level), a value of the wrong type, or
    /// options that [`Options::validate`] refuses.
    pub fn set(&mut self, assignment: &str) -> Result<(), StepError> {
        let bad = |m: String| StepError::InvalidInput(format!("{assignment}: {m}"));
        let (path, text) = assignment
            .split_once('=')
            .ok_or_else(|| bad("expected NAME=VALUE".into()))?;
        let mut doc = serde_json::to_value(&*self).map_err(|e| bad(e.to_string()))?;
        *slot(&mut doc, path.trim()).map_err(bad)? = parse(text.trim());
        let options: Self = serde_json::from_value(doc).map_err(|e| bad(e.to_string()))?;
        options.validate().map_err(|e| bad(e.to_string()))?;
        *self = options;
        Ok(())
    }
}

/// The value at `path` (keys joined by dots) of a JSON document of nested objects.
fn slot<'a>(doc: &'a mut Value, path: &str) -> Result<&'a mut Value, String> {
    let mut at = doc;
    for key in path.split('.') {
        let Value::Object(fields) = at else {
            return Err(format!("{key} is inside an option that has no parts"));
        };
        let names = fields.keys().cloned().collect::<Vec<_>>().join(", ");
        at = fields
            .get_mut(key)
            .ok_or_else(|| format!("no option {key:?} here; the options are {names}"))?;
    }
    Ok(at)
}

/// A JSON value, or the text itself as a string (`Sparse`, `self_consistent`).
fn parse(text: &str) -> Value {
    serde_json::from_str(text).unwrap_or_else(|_| Value::String(text.to_owned()))
}

#[cfg(test)]
mod tests {
    use crate::options::{Options, SolverChoice};

    #[test]
    fn an_assignment_sets_one_option_and_leaves_the_others() {
        let mut o = Options::default();
        o.set("newton.max_iter=7").unwrap();
        o.set("linear.solver=Dense").unwrap();
        o.set("tuning.prune_margin=3.5").unwrap();
        let mut expected = Options::default();
        expected.newton.max_iter = 7;
        expected.linear.solver = SolverChoice::Dense;
        expected.tuning.prune_margin = 3.5;
        assert_eq!(o, expected);
    }

    #[test]
    fn a_bad_assignment_names_itself_and_changes_nothing() {
        let mut o = Options::default();
        for (a, says) in [
            ("newton.max_iter", "NAME=VALUE"),
            ("newton.max_iters=3", "max_iter"),
            ("newton.max_iter=-1", "newton.max_iter=-1"),
            ("newton.max_iter=0", "max_iter"),
            ("dt.x=1", "no parts"),
            ("tuning.progress=-0.5", "progress"),
        ] {
            let e = o.set(a).unwrap_err().to_string();
            assert!(e.contains(says), "{a}: {e}");
        }
        assert_eq!(o, Options::default());
    }
}
