//! Which Kane kernel a run uses.

use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::kernel::Kernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::reference::ReferenceKernel;

/// The kernel a user asks for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum KernelChoice {
    /// The generic formulation of the paper's Eqs. 1–27 (slow, the oracle).
    Reference,
    /// Code emitted by `kanestop-codegen`, with the O(N) recursive solve: the unrolled kernel
    /// when the build has one for the chain's N, else the rolled kernel (any N). A chain that
    /// breaks a structural zero (which no scene builds) gets the reference, with a note.
    #[default]
    Generated,
}

impl std::str::FromStr for KernelChoice {
    type Err = String;

    /// The choice of its [`KernelChoice::name`], or what the valid names are.
    fn from_str(name: &str) -> Result<KernelChoice, String> {
        [KernelChoice::Generated, KernelChoice::Reference]
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| format!("kernel = {name:?}: must be \"generated\" or \"reference\""))
    }
}

impl KernelChoice {
    /// `reference` or `generated`.
    pub fn name(self) -> &'static str {
        match self {
            KernelChoice::Reference => "reference",
            KernelChoice::Generated => "generated",
        }
    }

    /// The kernel for `model`, and a note when the choice could not be honoured.
    pub fn build(self, model: &Model) -> (Box<dyn Kernel>, Option<String>) {
        match self {
            KernelChoice::Reference => (Box::new(ReferenceKernel::new(&model.chain)), None),
            KernelChoice::Generated => match GeneratedKernel::new(&model.chain) {
                Ok(k) => (Box::new(k), None),
                Err(e) => {
                    (Box::new(ReferenceKernel::new(&model.chain)), Some(format!("{e}; using the reference kernel")))
                }
            },
        }
    }
}

/// Builds the kernel of each run of a workflow.
pub type KernelFactory<'a> = &'a (dyn Fn(&Model) -> Box<dyn Kernel> + Sync);

/// The factory of `choice`: its notes go to standard error, once per run.
pub fn factory(choice: KernelChoice) -> impl Fn(&Model) -> Box<dyn Kernel> + Sync {
    move |model: &Model| {
        let (kernel, note) = choice.build(model);
        if let Some(note) = note {
            eprintln!("note: {note}");
        }
        kernel
    }
}
