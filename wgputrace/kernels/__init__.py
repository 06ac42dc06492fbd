"""What a kernel compiles in: the KernelVariant (variant.py), the generated files its hooks write
(hooks.py and one module per hook), the bind groups it declares, and the compiled-kernel cache."""
