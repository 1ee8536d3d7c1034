//! Specialising the shading module for one pipeline before the driver sees it.
//!
//! Every method of every family is one WGSL module (pipelines.rs), and a pipeline picks its
//! methods with override constants (`AREA_METHOD`, `DETAIL_METHOD`, …) tested in `if` and
//! `switch` statements. wgpu substitutes the constants and drops what no entry point reaches,
//! but the branches of the methods not picked stay in the SPIR-V it hands the driver: each
//! pipeline carries every method's code, and the driver's front end (lavapipe's
//! SPIR-V-to-NIR translation and optimisation) spends its time on all of it before its own
//! constant folding throws most of it away. On lavapipe that front end was 88 % of a study's
//! wall time (81 pipelines of `detail-view-angle`, 1.7 s each on average).
//!
//! So the module is specialised here, in naga's IR, for the pipeline's two entry points and
//! constants:
//!
//! 1. naga's own override processing ([`naga::back::pipeline_constants::process_overrides`])
//!    keeps the two entry points and what they reach, replaces each override by its value and
//!    folds the constant expressions, so a test such as `DETAIL_METHOD == DETAIL_POM` becomes
//!    a boolean literal;
//! 2. [`prune_block`] replaces an `if` on a literal by the branch taken and a `switch` on a
//!    literal by the case taken (kept as the single `default` case of a switch, so a `break`
//!    in it still leaves the switch and not an enclosing loop);
//! 3. compaction ([`naga::compact::compact`]) drops the expressions, functions, globals and
//!    types only the dropped branches used.
//!
//! The result is the code the driver would have kept, so the image is the same (the realtime
//! tests and the studies' metrics are the check); only the work of compiling it shrinks.
//! Expressions are pure in naga's IR (calls and stores are statements), so dropping a
//! branch's expressions, or the names `let` gave them, removes no effect.

use std::borrow::Cow;

use naga::back::pipeline_constants::process_overrides;
use naga::back::PipelineConstants;
use naga::{Block, Expression, Literal, Module, Statement, SwitchCase, SwitchValue};

/// The shading module parsed and validated once, specialised per pipeline.
pub(crate) struct ShaderIr {
    module: Module,
}

impl ShaderIr {
    /// Parses and validates WGSL `source`; an error is a bug in Verity's shaders, reported
    /// with naga's message (file positions are of the concatenated source).
    pub(crate) fn parse(source: &str) -> Result<Self, String> {
        let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
        validator()
            .validate(&module)
            .map_err(|e| e.emit_to_string(source))?;
        Ok(Self { module })
    }

    /// The module of one render pipeline: entry points `vertex` and `fragment` (if any) only,
    /// `constants` substituted, the branches they rule out and everything only those reached
    /// removed. It has no overrides left.
    pub(crate) fn specialise(
        &self,
        vertex: &str,
        fragment: Option<&str>,
        constants: &[(&str, f64)],
    ) -> Result<Module, String> {
        let mut module = self.module.clone();
        module
            .entry_points
            .retain(|ep| ep.name == vertex || Some(ep.name.as_str()) == fragment);
        let info = validator()
            .validate(&module)
            .map_err(|e| format!("{vertex}/{fragment:?}: {e}"))?;
        let constants: PipelineConstants = constants
            .iter()
            .map(|&(name, value)| (name.to_string(), value))
            .collect();
        let (processed, _) = process_overrides(&module, &info, None, &constants)
            .map_err(|e| format!("{vertex}/{fragment:?}: {e}"))?;
        let mut module = match processed {
            Cow::Owned(m) => m,
            Cow::Borrowed(m) => m.clone(),
        };
        let Module {
            ref mut functions,
            ref mut entry_points,
            ref constants,
            ref global_expressions,
            ..
        } = module;
        let bodies = functions
            .iter_mut()
            .map(|(_, f)| f)
            .chain(entry_points.iter_mut().map(|ep| &mut ep.function));
        for function in bodies {
            let literal = |h: naga::Handle<Expression>| match function.expressions[h] {
                Expression::Literal(l) => Some(l),
                Expression::Constant(c) => match global_expressions[constants[c].init] {
                    Expression::Literal(l) => Some(l),
                    _ => None,
                },
                _ => None,
            };
            let mut body = std::mem::take(&mut function.body);
            prune_block(&mut body, &literal);
            function.body = body;
            // `let` names keep expressions alive through compaction; they are debug names only.
            function.named_expressions.clear();
        }
        naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
        validator()
            .validate(&module)
            .map_err(|e| format!("{vertex}/{fragment:?} after specialising: {e}"))?;
        Ok(module)
    }
}

/// A validator accepting everything the WGSL front end can produce; wgpu validates the
/// specialised module again against the device's capabilities.
fn validator() -> naga::valid::Validator {
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
}

/// Replaces, in `block` and every block nested in it, each `if` whose condition `literal`
/// resolves by the statements of the branch taken, and each `switch` whose selector resolves
/// by a switch with only the case taken.
fn prune_block(block: &mut Block, literal: &impl Fn(naga::Handle<Expression>) -> Option<Literal>) {
    let old = std::mem::take(block);
    for (mut statement, span) in old.span_into_iter() {
        match statement {
            Statement::If {
                condition,
                ref mut accept,
                ref mut reject,
            } => match literal(condition) {
                Some(Literal::Bool(taken)) => {
                    let mut branch = std::mem::take(if taken { accept } else { reject });
                    prune_block(&mut branch, literal);
                    block.append(&mut branch);
                    continue;
                }
                _ => {
                    prune_block(accept, literal);
                    prune_block(reject, literal);
                }
            },
            Statement::Switch {
                selector,
                ref mut cases,
            } => {
                let value = match literal(selector) {
                    Some(Literal::U32(v)) => Some(SwitchValue::U32(v)),
                    Some(Literal::I32(v)) => Some(SwitchValue::I32(v)),
                    _ => None,
                };
                if let Some(value) = value {
                    // The case taken is the first whose value matches, else the default; a
                    // WGSL case of several values (`case 1u, 2u: {…}`) is one empty case per
                    // value falling through to the last, so the body is that case's and the
                    // bodies it falls through to.
                    let taken = cases
                        .iter()
                        .position(|c| c.value == value)
                        .or_else(|| cases.iter().position(|c| c.value == SwitchValue::Default));
                    if let Some(first) = taken {
                        let mut body = Block::new();
                        for case in &mut cases[first..] {
                            body.append(&mut case.body);
                            if !case.fall_through {
                                break;
                            }
                        }
                        prune_block(&mut body, literal);
                        *cases = vec![SwitchCase {
                            value: SwitchValue::Default,
                            body,
                            fall_through: false,
                        }];
                    }
                } else {
                    for case in cases.iter_mut() {
                        prune_block(&mut case.body, literal);
                    }
                }
            }
            Statement::Block(ref mut inner) => prune_block(inner, literal),
            Statement::Loop {
                ref mut body,
                ref mut continuing,
                ..
            } => {
                prune_block(body, literal);
                prune_block(continuing, literal);
            }
            _ => {}
        }
        block.push(statement, span);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SOURCE: &str = "
        override METHOD: u32 = 0u;
        fn cheap() -> f32 { return 1.0; }
        fn costly(x: f32) -> f32 { return x * x + sin(x); }
        @fragment fn fs() -> @location(0) vec4<f32> {
            var v = 0.0;
            if METHOD == 1u { let c = costly(2.0); v = c; } else { v = cheap(); }
            loop {
                switch METHOD { case 1u, 2u: { v += costly(v); break; } default: { v += 1.0; } }
                if v > 3.0 { break; }
            }
            return vec4<f32>(v);
        }
        @vertex fn vs() -> @builtin(position) vec4<f32> { return vec4<f32>(0.0); }
    ";

    fn function_names(m: &Module) -> Vec<String> {
        m.functions.iter().filter_map(|(_, f)| f.name.clone()).collect()
    }

    /// The branches the constant rules out go, with the functions only they called; a
    /// `switch` keeps its taken case as a switch, so its `break` still leaves the switch.
    #[test]
    fn the_branches_a_constant_rules_out_and_what_they_call_are_removed() {
        let ir = ShaderIr::parse(SOURCE).unwrap();
        let cheap = ir.specialise("vs", Some("fs"), &[("METHOD", 0.0)]).unwrap();
        assert_eq!(function_names(&cheap), ["cheap"]);
        assert!(cheap.overrides.is_empty());
        let costly = ir.specialise("vs", Some("fs"), &[("METHOD", 1.0)]).unwrap();
        assert_eq!(function_names(&costly), ["costly"]);
        // METHOD 2 reaches `costly` only through the case it shares with 1 (`case 1u, 2u`):
        // the `if` takes `cheap`, the switch's shared body `costly`.
        let shared = ir.specialise("vs", Some("fs"), &[("METHOD", 2.0)]).unwrap();
        assert_eq!(function_names(&shared), ["cheap", "costly"]);
        let fs = &costly
            .entry_points
            .iter()
            .find(|e| e.name == "fs")
            .unwrap()
            .function;
        let switches = fs
            .body
            .iter()
            .filter_map(|s| match s {
                Statement::Loop { body, .. } => Some(body),
                _ => None,
            })
            .flat_map(|b| b.iter())
            .filter(|s| matches!(s, Statement::Switch { cases, .. } if cases.len() == 1))
            .count();
        assert_eq!(switches, 1, "the taken case stays in a one-case switch");
        assert_eq!(costly.entry_points.len(), 2);
    }

    /// Without a value for the override its default applies, as in wgpu.
    #[test]
    fn an_override_left_out_takes_its_default() {
        let ir = ShaderIr::parse(SOURCE).unwrap();
        let m = ir.specialise("vs", Some("fs"), &[]).unwrap();
        assert_eq!(function_names(&m), ["cheap"]);
    }
}
