// Written once by iface from injection_docs.iface: this file is yours to edit. `iface-lsp generate` never
// overwrites it, not even with --force. Inject.hpp and Inject.cpp are regenerated
// from the interface; when it changes, the compiler names the hooks below that no longer match.

#include "Inject.hpp"

#include <drivers/drv_hrt.h>

void Inject::on_start()
{
}

void Inject::on_parameters_updated()
{
	// _param_inj_gain.get(): INJ_GAIN
	// _param_inj_on.get(): INJ_ON
}

void Inject::on_cycle()
{
	// probe_s probe{};
	// probe.timestamp = hrt_absolute_time();
	// _probe_pub.publish(probe);
}
