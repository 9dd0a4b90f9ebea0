//! The body counts N the scene files need: N = 1 + chain.elements + Σ cable stage
//! elements + 2 (anchor, links, cable elements, rod, ship).
//!
//! Deliberately minimal: it reads only the counts, so the build script does not depend on
//! the runtime's scene model (which itself depends on the generated kernels). A function of
//! a file's text: the callers read the files (the generator does no I/O).

/// N of one scene file's text, or why it has none.
pub fn body_count(text: &str) -> Result<usize, String> {
    let value: toml::Value = text.parse().map_err(|e| format!("not TOML: {e}"))?;
    let count = |v: Option<&toml::Value>, what: &str| -> Result<usize, String> {
        let v = v.and_then(toml::Value::as_integer).ok_or_else(|| format!("{what} is missing"))?;
        usize::try_from(v).map_err(|_| format!("{what} = {v} is negative"))
    };
    let links = count(value.get("chain").and_then(|c| c.get("elements")), "chain.elements")?;
    let stages = value
        .get("cable")
        .and_then(|c| c.get("stages"))
        .and_then(toml::Value::as_array)
        .ok_or("cable.stages is missing")?;
    let mut cable = 0;
    for s in stages {
        cable += count(s.get("elements"), "cable.stages.elements")?;
    }
    Ok(1 + links + cable + 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_bodies_of_a_scene() {
        let text = "[chain]\nelements = 15\n[cable]\n[[cable.stages]]\nelements = 3\n[[cable.stages]]\nelements = 12\n\
                    [[cable.stages]]\nelements = 13\n";
        assert_eq!(body_count(text), Ok(46));
        assert!(body_count("[chain]\n").is_err());
    }
}
