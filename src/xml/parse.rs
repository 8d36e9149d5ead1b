//! quick-xml's event reader turned into a small element tree that keeps the
//! byte span of every start tag, so later checks can point at the source.

use crate::source::Located;
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::path::Path;

#[derive(Debug, Clone)]
pub struct Attr {
    pub key: String,
    pub value: String,
}

#[derive(Debug, Clone)]
pub struct Element {
    pub tag: String,
    pub attrs: Vec<Attr>,
    pub children: Vec<Element>,
    /// Byte range of the start tag.
    pub start: usize,
    pub end: usize,
    /// Text content (only kept for port descriptions in models).
    pub text: String,
}

impl Element {
    pub fn attr(&self, key: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|a| a.key == key)
            .map(|a| a.value.as_str())
    }
}

/// Parses a whole document and returns its top element.
/// The deepest nesting of elements read, as tinyxml2's
/// TINYXML2_MAX_ELEMENT_DEPTH (BehaviorTree.CPP reads XML with tinyxml2).
pub const NESTING_MAX: usize = 500;

/// The longest element name, attribute name, and `ID` or `name` value: names
/// are shown on every screen and matched by the finder.
pub const NAME_MAX: usize = 4096;
/// The longest other attribute value (a port, a script) or text.
pub const ATTRIBUTE_MAX: usize = 1 << 20;

pub fn parse_document(path: &Path, text: &str) -> Result<Element, Located> {
    let mut reader = Reader::from_str(text);
    reader.config_mut().trim_text(true);
    let mut stack: Vec<Element> = Vec::new();
    let mut top: Option<Element> = None;
    loop {
        let prev_end = reader.buffer_position() as usize;
        let event = match reader.read_event() {
            Ok(ev) => ev,
            Err(e) => {
                let pos = reader.error_position() as usize;
                let end = (pos + 1).min(text.len());
                return Err(Located::at(
                    path,
                    text,
                    pos,
                    end,
                    format!("malformed XML: {e}"),
                ));
            }
        };
        // With trimming, the whitespace before a tag belongs to no event.
        let start = prev_end + text[prev_end.min(text.len())..].find('<').unwrap_or(0);
        let end = reader.buffer_position() as usize;
        match event {
            Event::Start(e) => {
                if stack.len() >= NESTING_MAX {
                    return Err(Located::at(
                        path,
                        text,
                        start,
                        end,
                        format!("elements nest deeper than {NESTING_MAX} levels, which BehaviorTree.CPP's XML reader (tinyxml2) refuses too"),
                    ));
                }
                let el = element(path, text, &e, start, end)?;
                stack.push(el);
            }
            Event::Empty(e) => {
                let el = element(path, text, &e, start, end)?;
                attach(path, text, &mut stack, &mut top, el)?;
            }
            Event::End(_) => {
                let el = stack.pop().expect("quick-xml checks end names");
                attach(path, text, &mut stack, &mut top, el)?;
            }
            Event::Text(t) => {
                if let Some(cur) = stack.last_mut() {
                    cur.text.push_str(&t);
                }
            }
            Event::CData(t) => {
                if let Some(cur) = stack.last_mut() {
                    cur.text.push_str(&t);
                }
            }
            Event::GeneralRef(r) => {
                if let Some(cur) = stack.last_mut() {
                    if let Ok(Some(c)) = r.resolve_char_ref() {
                        cur.text.push(c);
                    } else if let Some(s) = quick_xml::escape::resolve_predefined_entity(&r) {
                        cur.text.push_str(s);
                    }
                }
            }
            Event::Eof => break,
            Event::Comment(_) | Event::Decl(_) | Event::PI(_) | Event::DocType(_) => {}
        }
    }
    if let Some(open) = stack.last() {
        return Err(Located::at(
            path,
            text,
            open.start,
            open.end,
            format!("malformed XML: <{}> is never closed", open.tag),
        ));
    }
    top.ok_or_else(|| {
        Located::at(
            path,
            text,
            text.len(),
            text.len(),
            "malformed XML: the document has no element",
        )
    })
}

fn attach(
    path: &Path,
    text: &str,
    stack: &mut [Element],
    top: &mut Option<Element>,
    el: Element,
) -> Result<(), Located> {
    match stack.last_mut() {
        Some(parent) => parent.children.push(el),
        None if top.is_none() => *top = Some(el),
        None => {
            return Err(Located::at(
                path,
                text,
                el.start,
                el.end,
                "malformed XML: more than one top-level element",
            ))
        }
    }
    Ok(())
}

fn element(
    path: &Path,
    text: &str,
    e: &BytesStart,
    start: usize,
    end: usize,
) -> Result<Element, Located> {
    let tag = e.name().0.to_string();
    let too_long = |what: &str, len: usize, max: usize| {
        Located::at(
            path,
            text,
            start,
            end,
            format!("{what} is {len} bytes long, more than the {max} bytes btx reads"),
        )
    };
    if tag.len() > NAME_MAX {
        return Err(too_long("the element name", tag.len(), NAME_MAX));
    }
    let mut attrs = Vec::new();
    for a in e.attributes() {
        let a = a.map_err(|err| {
            Located::at(
                path,
                text,
                start,
                end,
                format!("malformed XML attribute: {err}"),
            )
        })?;
        let value = a
            .normalized_value(quick_xml::XmlVersion::Implicit1_0)
            .map_err(|err| {
                Located::at(
                    path,
                    text,
                    start,
                    end,
                    format!("malformed XML attribute value: {err}"),
                )
            })?;
        let key = a.key.0.to_string();
        if key.len() > NAME_MAX {
            return Err(too_long("an attribute name", key.len(), NAME_MAX));
        }
        let max = if matches!(key.as_str(), "ID" | "name") {
            NAME_MAX
        } else {
            ATTRIBUTE_MAX
        };
        if value.len() > max {
            return Err(too_long(&format!("attribute {key}"), value.len(), max));
        }
        attrs.push(Attr {
            key,
            value: value.into_owned(),
        });
    }
    Ok(Element {
        tag,
        attrs,
        children: Vec::new(),
        start,
        end,
        text: String::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_spans_of_start_tags() {
        let src = "<root>\n  <A x=\"1\"/>\n  <B>\n  </B>\n</root>";
        let root = parse_document(Path::new("t.xml"), src).unwrap();
        assert_eq!(root.children.len(), 2);
        let a = &root.children[0];
        assert_eq!(&src[a.start..a.end], "<A x=\"1\"/>");
        assert_eq!(a.attr("x"), Some("1"));
        let b = &root.children[1];
        assert_eq!(&src[b.start..b.end], "<B>");
    }

    #[test]
    fn mismatched_tags_are_located() {
        let src = "<root>\n  <Sequence>\n  </Fallback>\n</root>";
        let e = parse_document(Path::new("bad.xml"), src).unwrap_err();
        assert!(
            e.to_string().starts_with("bad.xml:3:3: malformed XML"),
            "{e}"
        );
    }

    #[test]
    fn unclosed_element_is_located() {
        let src = "<root>\n  <Sequence>";
        let e = parse_document(Path::new("bad.xml"), src).unwrap_err();
        assert!(e.to_string().starts_with("bad.xml:"), "{e}");
        assert!(e.to_string().contains("malformed XML"), "{e}");
    }
}
