//! The model's page in documentation/index.html (the runtime adds the variable tables).

pub const HTML: &str = r#"
<p>TODO</p>
"#;
