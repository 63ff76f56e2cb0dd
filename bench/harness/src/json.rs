//! A minimal JSON writer for the results file (objects of strings, numbers and lists; no
//! dependency for so little).

pub struct Json(Vec<(String, String)>);

fn number(v: f64) -> String {
    if v.is_finite() {
        format!("{v:e}")
    } else {
        "null".into()
    }
}

fn string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

impl Json {
    pub fn object() -> Self {
        Json(Vec::new())
    }

    pub fn str(mut self, key: &str, value: &str) -> Self {
        self.0.push((key.into(), string(value)));
        self
    }

    pub fn num(mut self, key: &str, value: f64) -> Self {
        self.0.push((key.into(), number(value)));
        self
    }

    pub fn opt_num(self, key: &str, value: Option<f64>) -> Self {
        match value {
            Some(v) => self.num(key, v),
            None => self,
        }
    }

    pub fn nums(mut self, key: &str, values: &[f64]) -> Self {
        let items: Vec<String> = values.iter().map(|v| number(*v)).collect();
        self.0.push((key.into(), format!("[{}]", items.join(", "))));
        self
    }

    pub fn list(mut self, key: &str, items: Vec<Json>) -> Self {
        let rendered: Vec<String> = items.iter().map(Json::render).collect();
        self.0.push((key.into(), format!("[\n{}\n]", rendered.join(",\n"))));
        self
    }

    /// A list of already rendered JSON values.
    pub fn raw_list(mut self, key: &str, items: Vec<String>) -> Self {
        self.0.push((key.into(), format!("[\n{}\n]", items.join(",\n"))));
        self
    }

    pub fn render(&self) -> String {
        let fields: Vec<String> = self.0.iter().map(|(k, v)| format!("{}: {v}", string(k))).collect();
        format!("{{{}}}", fields.join(", "))
    }
}
