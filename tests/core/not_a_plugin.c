/* not_a_plugin.c - a shared object without the plugin entry point. */
int pl_test_not_a_plugin(void);
int pl_test_not_a_plugin(void) { return 42; }
