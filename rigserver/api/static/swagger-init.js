// rig: starts Swagger UI on /docs. A file of its own, not an inline script, so that the
// page runs under a Content-Security-Policy of script-src 'self'. The document's address
// is the data-openapi-url of the #swagger-ui element.
(function () {
  "use strict";

  const root = document.getElementById("swagger-ui");
  window.ui = SwaggerUIBundle({
    url: root.dataset.openapiUrl,
    dom_id: "#swagger-ui",
    layout: "BaseLayout",
    deepLinking: true,
    showExtensions: true,
    showCommonExtensions: true,
    validatorUrl: null, // no badge from the online validator: the page stays on this server
    presets: [SwaggerUIBundle.presets.apis, SwaggerUIBundle.SwaggerUIStandalonePreset],
  });
})();
