//! Shared by the sheet's tests: the JSON Schema of the sheet and a small
//! validator for the keywords that schema uses (`type`, `properties`,
//! `required`, `additionalProperties: false`, `items`, `minItems`,
//! `maxItems`, `enum`, `const`, `minimum`, and `$ref` to `#/$defs/…`). A
//! keyword the validator does not know fails the test, so the schema
//! cannot grow a rule that is silently not checked.

#![allow(dead_code)]

use serde_json::Value;

/// The text of every element of `page` that `css` selects, in order.
pub fn select_text(page: &scraper::Html, css: &str) -> Vec<String> {
    let selector = scraper::Selector::parse(css).expect("selector");
    page.select(&selector)
        .map(|e| e.text().collect::<String>())
        .collect()
}

pub fn schema() -> Value {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/docs/sheet.schema.json"
    ))
    .expect("the schema file");
    serde_json::from_str(&text).expect("the schema is JSON")
}

/// Every place `instance` breaks `schema`, as `path: what`.
pub fn validate(schema: &Value, instance: &Value) -> Vec<String> {
    let mut problems = Vec::new();
    check(schema, schema, instance, "", &mut problems);
    problems
}

const KNOWN: &[&str] = &[
    "$schema",
    "$id",
    "$defs",
    "$ref",
    "title",
    "description",
    "type",
    "properties",
    "required",
    "additionalProperties",
    "items",
    "minItems",
    "maxItems",
    "enum",
    "const",
    "minimum",
];

fn type_matches(name: &str, value: &Value) -> bool {
    match name {
        "object" => value.is_object(),
        "array" => value.is_array(),
        "string" => value.is_string(),
        "boolean" => value.is_boolean(),
        "null" => value.is_null(),
        "number" => value.is_number(),
        "integer" => value.is_i64() || value.is_u64(),
        other => panic!("unknown type {other} in the schema"),
    }
}

fn check(root: &Value, schema: &Value, value: &Value, path: &str, problems: &mut Vec<String>) {
    let Some(rules) = schema.as_object() else {
        panic!("{path}: a schema that is not an object");
    };
    for key in rules.keys() {
        assert!(
            KNOWN.contains(&key.as_str()),
            "the schema uses `{key}`, which this validator does not check"
        );
    }
    if let Some(Value::String(reference)) = rules.get("$ref") {
        let pointer = reference.strip_prefix('#').expect("a local $ref");
        let target = root.pointer(pointer).expect("the $ref resolves");
        check(root, target, value, path, problems);
    }
    if let Some(types) = rules.get("type") {
        let names: Vec<&str> = match types {
            Value::String(one) => vec![one.as_str()],
            Value::Array(many) => many.iter().filter_map(Value::as_str).collect(),
            _ => panic!("{path}: odd type"),
        };
        if !names.iter().any(|n| type_matches(n, value)) {
            problems.push(format!("{path}: {value} is not {names:?}"));
            return;
        }
    }
    if let Some(constant) = rules.get("const")
        && constant != value
    {
        problems.push(format!("{path}: {value} is not {constant}"));
    }
    if let Some(Value::Array(choices)) = rules.get("enum")
        && !choices.contains(value)
    {
        problems.push(format!("{path}: {value} is not one of {choices:?}"));
    }
    if let (Some(minimum), Some(number)) =
        (rules.get("minimum").and_then(Value::as_f64), value.as_f64())
        && number < minimum
    {
        problems.push(format!("{path}: {number} < {minimum}"));
    }
    if let Value::Object(map) = value {
        if let Some(Value::Array(required)) = rules.get("required") {
            for name in required.iter().filter_map(Value::as_str) {
                if !map.contains_key(name) {
                    problems.push(format!("{path}: `{name}` missing"));
                }
            }
        }
        let properties = rules.get("properties").and_then(Value::as_object);
        for (name, item) in map {
            match properties.and_then(|p| p.get(name)) {
                Some(sub) => check(root, sub, item, &format!("{path}/{name}"), problems),
                None if rules.get("additionalProperties") == Some(&Value::Bool(false)) => {
                    problems.push(format!("{path}: `{name}` is not in the schema"));
                }
                None => {}
            }
        }
    }
    if let Value::Array(items) = value {
        if let Some(min) = rules.get("minItems").and_then(Value::as_u64)
            && (items.len() as u64) < min
        {
            problems.push(format!("{path}: fewer than {min} items"));
        }
        if let Some(max) = rules.get("maxItems").and_then(Value::as_u64)
            && (items.len() as u64) > max
        {
            problems.push(format!("{path}: more than {max} items"));
        }
        if let Some(item_schema) = rules.get("items") {
            for (index, item) in items.iter().enumerate() {
                check(
                    root,
                    item_schema,
                    item,
                    &format!("{path}/{index}"),
                    problems,
                );
            }
        }
    }
}
