//! Program → machine code with Cranelift: each operation of a [`Program`] becomes one
//! instruction (or one call, for the elementary functions), in the program's order, so the code
//! rounds exactly as the Rust the attribute emits for the same program: `+ − · /`, negation and
//! `sqrt` are IEEE-754 operations in both, there is no contraction into fused multiply-adds in
//! either, and every other function is a call to Rust's own `f64` method.
//!
//! Every kernel has one signature, `fn(params, a, b, c, d, out)` over `*const f64` (and
//! `*mut f64` for `out`): the parameters, up to four argument vectors, and the outputs, written
//! in order. Which argument a leaf reads is the kernel's [`Layout`].

use cranelift_codegen::ir::{types, AbiParam, InstBuilder, MemFlags, Signature, Value};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, FuncId, Linkage, Module};
use dirac_compiler::program::{Fun, Leaf, Op, Program};

use crate::error::Error;

/// A compiled kernel: parameters, up to four argument vectors, outputs.
pub type Kernel =
    unsafe extern "C" fn(*const f64, *const f64, *const f64, *const f64, *const f64, *mut f64);

/// Where a kernel reads each leaf: `(argument, index)`, argument 0 the parameters and 1–4 the
/// vectors `a`–`d`.
pub type Layout<'a> = &'a dyn Fn(Leaf) -> (usize, usize);

/// The elementary functions the kernels call: Rust's own `f64` methods behind the C ABI, with
/// their symbols (`sqrt` and `recip` are instructions).
macro_rules! calls {
    ($($fun:ident => $name:ident, $method:path;)*) => {
        $(
            extern "C" fn $name(x: f64) -> f64 {
                $method(x)
            }
        )*
        /// Each called function of one argument: its symbol and address.
        const CALLS: &[(Fun, &str, extern "C" fn(f64) -> f64)] = &[
            $((Fun::$fun, stringify!($name), $name),)*
        ];
    };
}

calls! {
    Sin => dirac_sin, f64::sin;
    Cos => dirac_cos, f64::cos;
    Tan => dirac_tan, f64::tan;
    Asin => dirac_asin, f64::asin;
    Acos => dirac_acos, f64::acos;
    Atan => dirac_atan, f64::atan;
    Exp => dirac_exp, f64::exp;
    Ln => dirac_ln, f64::ln;
    Sinh => dirac_sinh, f64::sinh;
    Cosh => dirac_cosh, f64::cosh;
    Tanh => dirac_tanh, f64::tanh;
}

/// The symbol of a called function of one argument.
fn symbol_of(f: Fun) -> &'static str {
    CALLS
        .iter()
        .find(|(g, _, _)| *g == f)
        .map_or("", |&(_, name, _)| name)
}

extern "C" fn dirac_powi(x: f64, n: i32) -> f64 {
    x.powi(n)
}

extern "C" fn dirac_powf(x: f64, y: f64) -> f64 {
    x.powf(y)
}

extern "C" fn dirac_atan2(y: f64, x: f64) -> f64 {
    y.atan2(x)
}

/// A Cranelift JIT module with the elementary functions resolved.
pub struct Jit {
    module: JITModule,
    context: cranelift_codegen::Context,
    builder: FunctionBuilderContext,
    defined: Vec<FuncId>,
}

impl Jit {
    /// A module for this machine's instruction set, optimizing for speed.
    pub fn new() -> Result<Jit, Error> {
        let mut flags = settings::builder();
        let set = |flags: &mut settings::Builder, k: &str, v: &str| {
            flags
                .set(k, v)
                .map_err(|e| Error::Codegen(format!("setting {k}: {e}")))
        };
        set(&mut flags, "use_colocated_libcalls", "false")?;
        set(&mut flags, "is_pic", "false")?;
        set(&mut flags, "opt_level", "speed")?;
        // Cranelift's IR verifier re-checks every function it is given (a fifth of a small
        // system's compile time): on in a build with debug assertions (`cargo test` without
        // `--release`), off in an optimized one, where the tests' bit-for-bit comparisons with
        // the compiled-in systems check the translation.
        let verify = if cfg!(debug_assertions) {
            "true"
        } else {
            "false"
        };
        set(&mut flags, "enable_verifier", verify)?;
        let isa = cranelift_native::builder()
            .map_err(|e| Error::Codegen(format!("this machine's instruction set: {e}")))?
            .finish(settings::Flags::new(flags))
            .map_err(|e| Error::Codegen(e.to_string()))?;
        let mut builder = JITBuilder::with_isa(isa, default_libcall_names());
        for &(_, name, f) in CALLS {
            builder.symbol(name, f as *const u8);
        }
        builder.symbol("dirac_powi", dirac_powi as *const u8);
        builder.symbol("dirac_powf", dirac_powf as *const u8);
        builder.symbol("dirac_atan2", dirac_atan2 as *const u8);
        let module = JITModule::new(builder);
        Ok(Jit {
            context: module.make_context(),
            module,
            builder: FunctionBuilderContext::new(),
            defined: Vec::new(),
        })
    }

    /// Translates `program` into a kernel reading its leaves as `layout` says; its address is
    /// known after [`Self::finish`], at the returned index.
    pub fn define(&mut self, program: &Program, layout: Layout) -> Result<usize, Error> {
        // Every operation is at least one value of the function, and Cranelift's register
        // allocator numbers at most 2²¹ of them: a larger program is refused before any work.
        if program.ops.len() >= MAX_VALUES {
            return Err(too_large(program));
        }
        let ptr = self.module.target_config().pointer_type();
        let mut sig = self.module.make_signature();
        for _ in 0..6 {
            sig.params.push(AbiParam::new(ptr));
        }
        self.context.func.signature = sig.clone();
        let callee = |module: &mut JITModule, name: &str, params: &[types::Type]| {
            let mut s = Signature::new(module.isa().default_call_conv());
            for &p in params {
                s.params.push(AbiParam::new(p));
            }
            s.returns.push(AbiParam::new(types::F64));
            module
                .declare_function(name, Linkage::Import, &s)
                .map_err(|e| Error::Codegen(e.to_string()))
        };
        let mut calls = Vec::new();
        for op in &program.ops {
            let (name, params): (&str, &[types::Type]) = match *op {
                Op::Fun(Fun::Sqrt | Fun::Recip, _) => continue,
                Op::Fun(f, _) => (symbol_of(f), &[types::F64]),
                Op::Powi(..) => ("dirac_powi", &[types::F64, types::I32]),
                Op::Powf(..) => ("dirac_powf", &[types::F64, types::F64]),
                Op::Atan2(..) => ("dirac_atan2", &[types::F64, types::F64]),
                _ => continue,
            };
            if !calls.iter().any(|(n, _)| *n == name) {
                calls.push((name, callee(&mut self.module, name, params)?));
            }
        }
        {
            let mut b = FunctionBuilder::new(&mut self.context.func, &mut self.builder);
            let refs: Vec<(&str, cranelift_codegen::ir::FuncRef)> = calls
                .iter()
                .map(|&(n, id)| (n, self.module.declare_func_in_func(id, b.func)))
                .collect();
            let call = |b: &mut FunctionBuilder, name: &str, args: &[Value]| -> Value {
                let f = refs
                    .iter()
                    .find(|(n, _)| *n == name)
                    .expect("declared above")
                    .1;
                let inst = b.ins().call(f, args);
                b.inst_results(inst)[0]
            };
            let block = b.create_block();
            b.append_block_params_for_function_params(block);
            b.switch_to_block(block);
            b.seal_block(block);
            let args = b.block_params(block).to_vec();
            let flags = MemFlags::trusted();
            let mut v: Vec<Value> = Vec::with_capacity(program.ops.len());
            for op in &program.ops {
                let x = |i: u32| v[i as usize];
                let value = match *op {
                    Op::Leaf(leaf) => {
                        let (arg, index) = layout(leaf);
                        b.ins().load(types::F64, flags, args[arg], offset(index)?)
                    }
                    Op::Const(c) => b.ins().f64const(c),
                    Op::Neg(a) => b.ins().fneg(x(a)),
                    Op::Add(a, c) => b.ins().fadd(x(a), x(c)),
                    Op::Sub(a, c) => b.ins().fsub(x(a), x(c)),
                    Op::Mul(a, c) => b.ins().fmul(x(a), x(c)),
                    Op::Div(a, c) => b.ins().fdiv(x(a), x(c)),
                    Op::Fun(Fun::Sqrt, a) => b.ins().sqrt(x(a)),
                    Op::Fun(Fun::Recip, a) => {
                        let one = b.ins().f64const(1.0);
                        b.ins().fdiv(one, x(a))
                    }
                    Op::Fun(f, a) => call(&mut b, symbol_of(f), &[x(a)]),
                    Op::Powi(a, n) => {
                        let n = b.ins().iconst(types::I32, i64::from(n));
                        call(&mut b, "dirac_powi", &[x(a), n])
                    }
                    Op::Powf(a, c) => call(&mut b, "dirac_powf", &[x(a), x(c)]),
                    Op::Atan2(y, c) => call(&mut b, "dirac_atan2", &[x(y), x(c)]),
                };
                v.push(value);
            }
            for (i, &o) in program.outputs.iter().enumerate() {
                b.ins().store(flags, v[o as usize], args[5], offset(i)?);
            }
            b.ins().return_(&[]);
            b.finalize();
        }
        let id = self
            .module
            .declare_anonymous_function(&sig)
            .map_err(|e| Error::Codegen(e.to_string()))?;
        self.module
            .define_function(id, &mut self.context)
            .map_err(|e| match e {
                cranelift_module::ModuleError::Compilation(
                    cranelift_codegen::CodegenError::CodeTooLarge,
                ) => too_large(program),
                e => Error::Codegen(format!("{e:?}")),
            })?;
        self.module.clear_context(&mut self.context);
        self.defined.push(id);
        Ok(self.defined.len() - 1)
    }

    /// Makes every defined kernel executable: their addresses, in definition order, and the
    /// module that owns their memory.
    pub fn finish(mut self) -> Result<(Vec<Kernel>, JITModule), Error> {
        self.module
            .finalize_definitions()
            .map_err(|e| Error::Codegen(e.to_string()))?;
        let kernels = self
            .defined
            .iter()
            .map(|&id| {
                let ptr = self.module.get_finalized_function(id);
                // SAFETY: every defined function has the kernel signature (`define`).
                unsafe { std::mem::transmute::<*const u8, Kernel>(ptr) }
            })
            .collect();
        Ok((kernels, self.module))
    }
}

/// The values one function may have: Cranelift's register allocator numbers its virtual
/// registers in 21 bits.
const MAX_VALUES: usize = 1 << 21;

/// The error for a program too large to become one function of machine code.
fn too_large(program: &Program) -> Error {
    Error::Codegen(format!(
        "a kernel of {} operations is too large for one function of machine code (Cranelift \
         numbers at most 2^21 values in a function, and an operation may take two): \
         shorten the Lagrangian (a sum of fewer terms, common factors taken out)",
        program.ops.len()
    ))
}

/// The byte offset of entry `i` of an `f64` array, as a load's immediate.
fn offset(i: usize) -> Result<i32, Error> {
    i.checked_mul(8)
        .and_then(|b| i32::try_from(b).ok())
        .ok_or_else(|| Error::Codegen(format!("entry {i} is beyond a kernel's reach")))
}
