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
//!    in it still leaves the switch and not an enclosing loop), and drops what follows a
//!    `return`, `break`, `continue` or `discard` in its block. A condition counts as a literal
//!    when [`Fold::literal`] decides it: naga folds `METHOD == 3u` but not `false && x`, nor a
//!    call to a helper such as `is_lightmapped(s)` whose pruned body is `return false && …;`;
//!    functions are pruned callees first, so such a helper's constant result is known where
//!    it is called;
//! 3. compaction ([`naga::compact::compact`]) drops the expressions, functions, globals and
//!    types only the dropped branches used.
//!
//! The result is the code the driver would have kept, so the image is the same (the realtime
//! tests and the studies' metrics are the check); only the work of compiling it shrinks.
//! Expressions are pure in naga's IR (calls and stores are statements), so dropping a
//! branch's expressions, or the names `let` gave them, removes no effect.

use std::borrow::Cow;
use std::collections::HashMap;

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

    /// The module of one pipeline: the entry points named in `entry_points` only (a render
    /// pipeline's vertex and fragment stage, or a compute pipeline's one),
    /// `constants` substituted, the branches they rule out and everything only those reached
    /// removed. It has no overrides left.
    pub(crate) fn specialise(
        &self,
        entry_points: &[&str],
        constants: &[(&str, f64)],
    ) -> Result<Module, String> {
        let mut module = self.module.clone();
        module
            .entry_points
            .retain(|ep| entry_points.contains(&ep.name.as_str()));
        let names = entry_points.join("/");
        let info = validator()
            .validate(&module)
            .map_err(|e| format!("{names}: {e}"))?;
        let constants: PipelineConstants = constants
            .iter()
            .map(|&(name, value)| (name.to_string(), value))
            .collect();
        let (processed, _) =
            process_overrides(&module, &info, None, &constants).map_err(|e| format!("{names}: {e}"))?;
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
        // Functions come before their callers in naga's arena, so a callee's constant
        // result is known when its callers are pruned.
        let mut returns = HashMap::new();
        for (handle, function) in functions.iter_mut() {
            if let Some(value) = prune_function(function, constants, global_expressions, &returns) {
                returns.insert(handle, value);
            }
        }
        for ep in entry_points.iter_mut() {
            prune_function(&mut ep.function, constants, global_expressions, &returns);
        }
        naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
        validator()
            .validate(&module)
            .map_err(|e| format!("{names} after specialising: {e}"))?;
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

/// Prunes `function`'s body ([`prune_block`]) given the constant results of the functions
/// it may call (`returns`), and returns the literal it then always returns, if any.
fn prune_function(
    function: &mut naga::Function,
    constants: &naga::Arena<naga::Constant>,
    global_expressions: &naga::Arena<Expression>,
    returns: &HashMap<naga::Handle<naga::Function>, Literal>,
) -> Option<Literal> {
    let fold = Fold {
        expressions: &function.expressions,
        constants,
        global_expressions,
        returns,
    };
    let mut body = std::mem::take(&mut function.body);
    prune_block(&mut body, &fold);
    let value = fold.constant_return(&body);
    function.body = body;
    // `let` names keep expressions alive through compaction; they are debug names only.
    function.named_expressions.clear();
    value
}

/// Replaces, in `block` and every block nested in it, each `if` whose condition `literal`
/// resolves by the statements of the branch taken, and each `switch` whose selector resolves
/// by a switch with only the case taken.
fn prune_block(block: &mut Block, fold: &Fold) {
    let old = std::mem::take(block);
    for (mut statement, span) in old.span_into_iter() {
        match statement {
            Statement::If {
                condition,
                ref mut accept,
                ref mut reject,
            } => match fold.literal(condition) {
                Some(Literal::Bool(taken)) => {
                    let mut branch = std::mem::take(if taken { accept } else { reject });
                    prune_block(&mut branch, fold);
                    block.append(&mut branch);
                    if ends_control_flow(block) {
                        return;
                    }
                    continue;
                }
                _ => {
                    prune_block(accept, fold);
                    prune_block(reject, fold);
                }
            },
            Statement::Switch {
                selector,
                ref mut cases,
            } => {
                let value = match fold.literal(selector) {
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
                        prune_block(&mut body, fold);
                        *cases = vec![SwitchCase {
                            value: SwitchValue::Default,
                            body,
                            fall_through: false,
                        }];
                    }
                } else {
                    for case in cases.iter_mut() {
                        prune_block(&mut case.body, fold);
                    }
                }
            }
            Statement::Block(ref mut inner) => prune_block(inner, fold),
            Statement::Loop {
                ref mut body,
                ref mut continuing,
                ..
            } => {
                prune_block(body, fold);
                prune_block(continuing, fold);
            }
            _ => {}
        }
        block.push(statement, span);
        if ends_control_flow(block) {
            return;
        }
    }
}

/// Whether `block` ends in a statement that leaves it (`return`, `break`, `continue`,
/// `discard`): what followed it there could never run.
fn ends_control_flow(block: &Block) -> bool {
    matches!(
        block.last(),
        Some(Statement::Return { .. } | Statement::Break | Statement::Continue | Statement::Kill)
    )
}

/// Constant folding of the conditions the override values decide, in one function.
struct Fold<'a> {
    expressions: &'a naga::Arena<Expression>,
    constants: &'a naga::Arena<naga::Constant>,
    global_expressions: &'a naga::Arena<Expression>,
    /// The functions already pruned whose every call returns this literal.
    returns: &'a HashMap<naga::Handle<naga::Function>, Literal>,
}

impl Fold<'_> {
    /// The literal `h` always evaluates to, if the override values decide it: a literal, a
    /// constant, a call to a function that returns one literal, and the logical operators on
    /// those. WGSL's `&&` and `||` short-circuit (WGSL spec, section 8.6, "Logical
    /// Expressions"), and naga's expressions are pure, so `false && x` is `false` whatever `x`.
    fn literal(&self, h: naga::Handle<Expression>) -> Option<Literal> {
        use naga::{BinaryOperator as B, UnaryOperator as U};
        match self.expressions[h] {
            Expression::Literal(l) => Some(l),
            Expression::Constant(c) => match self.global_expressions[self.constants[c].init] {
                Expression::Literal(l) => Some(l),
                _ => None,
            },
            Expression::CallResult(f) => self.returns.get(&f).copied(),
            Expression::Unary {
                op: U::LogicalNot,
                expr,
            } => match self.literal(expr) {
                Some(Literal::Bool(b)) => Some(Literal::Bool(!b)),
                _ => None,
            },
            Expression::Binary { op, left, right } => {
                let absorbing = match op {
                    B::LogicalAnd | B::And => false,
                    B::LogicalOr | B::InclusiveOr => true,
                    _ => return None,
                };
                match (self.literal(left), self.literal(right)) {
                    (Some(Literal::Bool(a)), _) if a == absorbing => Some(Literal::Bool(a)),
                    (_, Some(Literal::Bool(b))) if b == absorbing => Some(Literal::Bool(b)),
                    (Some(Literal::Bool(_)), Some(Literal::Bool(_))) => Some(Literal::Bool(!absorbing)),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// The literal a function with this (pruned) body always returns: its first statement
    /// other than an `Emit` returns a value that folds to one.
    fn constant_return(&self, body: &Block) -> Option<Literal> {
        match body.iter().find(|s| !matches!(s, Statement::Emit(_)))? {
            Statement::Return { value: Some(v) } => self.literal(*v),
            _ => None,
        }
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
        let cheap = ir.specialise(&["vs", "fs"], &[("METHOD", 0.0)]).unwrap();
        assert_eq!(function_names(&cheap), ["cheap"]);
        assert!(cheap.overrides.is_empty());
        let costly = ir.specialise(&["vs", "fs"], &[("METHOD", 1.0)]).unwrap();
        assert_eq!(function_names(&costly), ["costly"]);
        // METHOD 2 reaches `costly` only through the case it shares with 1 (`case 1u, 2u`):
        // the `if` takes `cheap`, the switch's shared body `costly`.
        let shared = ir.specialise(&["vs", "fs"], &[("METHOD", 2.0)]).unwrap();
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

    /// A condition that short-circuits on a constant, a helper that returns one constant
    /// result, and code after a `return` go too, with what only they called.
    #[test]
    fn short_circuits_constant_helpers_and_code_after_return_are_folded() {
        let source = "
            override ON: bool = false;
            @group(0) @binding(0) var<uniform> u: vec4<f32>;
            fn costly(x: f32) -> f32 { return x * x + sin(x); }
            fn later(x: f32) -> f32 { return exp(x); }
            fn enabled(x: f32) -> bool { return ON && x > 0.0; }
            fn kept(x: f32) -> f32 { if !ON || x < 0.0 { return x; } return costly(x); }
            fn early(x: f32) -> f32 { return x; let y = later(x); return y; }
            @fragment fn fs() -> @location(0) vec4<f32> {
                var v = kept(u.x) + early(u.y);
                if enabled(u.z) { v += costly(u.w); }
                return vec4<f32>(v);
            }
            @vertex fn vs() -> @builtin(position) vec4<f32> { return vec4<f32>(0.0); }
        ";
        let ir = ShaderIr::parse(source).unwrap();
        let off = ir.specialise(&["vs", "fs"], &[("ON", 0.0)]).unwrap();
        assert_eq!(function_names(&off), ["enabled", "kept", "early"]);
        let on = ir.specialise(&["vs", "fs"], &[("ON", 1.0)]).unwrap();
        assert_eq!(function_names(&on), ["costly", "enabled", "kept", "early"]);
    }

    /// Without a value for the override its default applies, as in wgpu.
    #[test]
    fn an_override_left_out_takes_its_default() {
        let ir = ShaderIr::parse(SOURCE).unwrap();
        let m = ir.specialise(&["vs", "fs"], &[]).unwrap();
        assert_eq!(function_names(&m), ["cheap"]);
    }
}
